//! The fretting profile in the stepping view (`f`): per node over the last
//! completed cycle, the envelopes of `p` and `q` with the friction bound,
//! the slip amplitude and the dissipation density (model.md section 4.1).
//! The worker computes it from a copy of the stepper kept where that cycle
//! began, on a thread of its own; while the panel is open a new profile is
//! asked for each time a cycle completes, one at a time.

use super::*;
use crate::analysis::profile::Profile;

/// The profile panel's state.
#[derive(Debug, Clone, Default)]
pub struct ProfilePanel {
    /// The panel replaces the bottom row of the stepping view.
    visible: bool,
    /// The profile on screen.
    profile: Option<Box<Profile>>,
    /// A profile has been asked for and not yet come back.
    pending: bool,
    /// The last completed cycle when a profile was last asked for: it is
    /// not asked for again until a later cycle completes, whatever cycle
    /// the answer was of.
    asked: Option<usize>,
    /// Why there is no profile: no cycle completed yet, or the solver's
    /// failure.
    missing: Option<String>,
}

impl ProfilePanel {
    /// Whether the panel is on screen.
    pub fn is_visible(&self) -> bool {
        self.visible
    }
    /// The profile of the last completed cycle, once it has come.
    pub fn profile(&self) -> Option<&Profile> {
        self.profile.as_deref()
    }
    /// A newer profile is being computed.
    pub fn is_pending(&self) -> bool {
        self.pending
    }
    /// Why there is no profile, when there is none.
    pub fn missing(&self) -> Option<&str> {
        self.missing.as_deref()
    }
    /// The run was replaced: its profile goes (the worker cancels the one
    /// in progress), the panel stays open.
    fn forget(&mut self) {
        self.profile = None;
        self.pending = false;
        self.asked = None;
        self.missing = None;
    }
}

/// The node of the largest Ruiz parameter (the fretting-fatigue hot spot),
/// `None` where nothing slips.
pub fn hot_spot(profile: &Profile) -> Option<usize> {
    profile
        .ruiz
        .iter()
        .enumerate()
        .filter(|(_, v)| **v > 0.0)
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(j, _)| j)
}

/// The hot spot in words, for the status line and the panel: `hot spot
/// (max Ruiz) at theta = 0.27pi`, or that nothing slipped.
pub fn hot_spot_text(profile: &Profile) -> String {
    match hot_spot(profile) {
        Some(j) => format!(
            "hot spot (max Ruiz) at θ = {:.2}π",
            node_theta(j, profile.theta.len()) / PI
        ),
        None => format!("nothing slips in cycle {}: no hot spot", profile.cycle),
    }
}

impl App {
    /// The profile panel's actions; false if `action` is not one.
    pub(super) fn profile_action(&mut self, action: Action) -> bool {
        match action {
            Action::ToggleProfile => {
                self.stepping.profile.visible = !self.stepping.profile.visible;
                if !self.stepping.profile.visible {
                    // Reopened, it says the hot spot again.
                    self.stepping.profile.forget();
                    self.notice = Some("fretting profile: off".into());
                    return true;
                }
                self.ask_profile();
                self.notice = Some(
                    match (self.stepping.cycles.last(), &self.stepping.profile.profile) {
                        (None, _) => {
                            "fretting profile: it comes when the first cycle completes".into()
                        }
                        (Some(&(c, _)), Some(p)) if p.cycle == c => {
                            format!("fretting profile of cycle {c}: {}", hot_spot_text(p))
                        }
                        (Some(&(c, _)), _) => format!("fretting profile of cycle {c}: computing…"),
                    },
                );
            }
            _ => return false,
        }
        true
    }

    /// The profile panel, for drawing.
    pub fn profile_panel(&self) -> &ProfilePanel {
        &self.stepping.profile
    }

    /// `W` of the cycle the profile on screen is of, as the run recorded
    /// it: the profile's dissipation column sums to it.
    pub fn profile_w(&self) -> Option<f64> {
        let p = self.stepping.profile.profile.as_ref()?;
        self.stepping
            .cycles
            .iter()
            .rev()
            .find(|c| c.0 == p.cycle)
            .map(|c| c.1)
    }

    /// Ask the worker for the profile of the last completed cycle, when
    /// the panel is open, none is in flight and the one on screen is older.
    pub(super) fn ask_profile(&mut self) {
        let panel = &self.stepping.profile;
        if !panel.visible || panel.pending {
            return;
        }
        let Some(&(last, _)) = self.stepping.cycles.last() else {
            return;
        };
        if panel.profile.as_ref().is_some_and(|p| p.cycle >= last)
            || panel.asked.is_some_and(|a| a >= last)
        {
            return;
        }
        self.stepping.profile.pending = true;
        self.stepping.profile.asked = Some(last);
        self.worker.send(Command::Profile);
    }

    /// The worker's answer for the current run.
    pub(super) fn take_profile(&mut self, profile: Result<Option<Box<Profile>>, String>) {
        let panel = &mut self.stepping.profile;
        panel.pending = false;
        match profile {
            Ok(Some(p)) => {
                // The first profile since the panel opened (or the run
                // restarted) says where the hot spot is on the status line.
                if panel.profile.is_none() {
                    self.notice = Some(format!(
                        "fretting profile of cycle {}: {}",
                        p.cycle,
                        hot_spot_text(&p)
                    ));
                }
                panel.missing = None;
                panel.profile = Some(p);
            }
            // No copy of a completed cycle's start yet: at more than
            // 1024 nodes the worker keeps them once a profile is asked for.
            Ok(None) => {
                panel.missing = Some("waiting for a cycle to complete from its start".into())
            }
            Err(e) => panel.missing = Some(format!("no profile: {e}")),
        }
    }

    /// The run restarted: its profile is no longer the one on screen.
    pub(super) fn forget_profile(&mut self) {
        self.stepping.profile.forget();
    }

    /// Show `profile` as if the worker had sent it: tests draw a fixed,
    /// synthetic profile with it, so snapshots hold no solver numbers.
    pub fn feed_profile(&mut self, profile: Profile) {
        self.stepping.profile.visible = true;
        self.take_profile(Ok(Some(Box::new(profile))));
    }
}
