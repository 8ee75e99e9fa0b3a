//! The guided tour: the paper's story in eight stops, each a live case
//! with a caption that traces to `docs/model.md`. While the tour has the
//! keys, `n` and `N` move between stops and Space runs or pauses; `Esc`
//! hands the case on screen to the user with every key back.

use super::*;

/// What a stop opens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scene {
    /// One case `(lambda, phi, initial path)`, running; with `pause_at`,
    /// it pauses at advancing-stick events of at least that many nodes.
    Case {
        /// `lambda`.
        load_factor: f64,
        /// `phi`, radians.
        phase: f64,
        /// The initial path, as `--initial` spells it.
        initial: &'static str,
        /// Pause at advancing stick of at least this many nodes.
        pause_at: Option<usize>,
    },
    /// Two cases pinned side by side: the first is run to its steady state
    /// and pinned, then the second is run to its own.
    Compare {
        /// The pinned case: `lambda`, `phi`, path.
        pinned: (f64, f64, &'static str),
        /// The live case: `lambda`, `phi`, path.
        live: (f64, f64, &'static str),
    },
    /// The regime map over `(lambda, phi)` for the direct path `OA`.
    Regime,
}

/// One stop of the tour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    /// The caption panel's title after `Tour k/n: `.
    pub title: &'static str,
    /// Two or three sentences, in the words of `docs/model.md`.
    pub caption: &'static str,
    /// What the stop opens.
    pub scene: Scene,
}

const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;

/// The stops, in the order of the paper's story.
pub const STOPS: [Stop; 8] = [
    Stop {
        title: "the stick diamond",
        caption: "From no slip, the interface sticks while the load stays in the diamond |x| + |y| <= 2 pi on the load plane (model.md 2.3): the direct path OA locks nothing in. At lambda = 3 the cycle leaves the diamond, slips in its first cycles and shakes down, as every history does below lambda_1 (model.md 7).",
        scene: Scene::Case {
            load_factor: 3.0,
            phase: 0.0,
            initial: "OA",
            pause_at: None,
        },
    },
    Stop {
        title: "advancing stick on a transient that leaves it",
        caption: "The transient 7,-7 leaves the diamond and slips on its way to A. Where a slip zone shrinks, its nodes stick again and keep the slip they gathered: advancing stick, found at its exact load point (model.md 3.3). The run pauses at each of 8 nodes or more; the slip panel shows what each locked in.",
        scene: Scene::Case {
            load_factor: 6.0,
            phase: 0.0,
            initial: "7,-7",
            pause_at: Some(8),
        },
    },
    Stop {
        title: "history dependence",
        caption: "Between lambda_1 and lambda_2 shakedown depends on the transient (model.md 7, 8: Fig. 3). At lambda = 4.75, phi = 0 the direct path OA shakes down (pinned, x), while 7,-7 locks in a slip that leaves it slipping every cycle (live, o). Both run to their steady states.",
        scene: Scene::Compare {
            pinned: (4.75, 0.0, "OA"),
            live: (4.75, 0.0, "7,-7"),
        },
    },
    Stop {
        title: "the optimal slip and lambda_2",
        caption: "lambda_2 is the largest lambda at which some locked-in slip holds the whole cycle in stick: a linear programme, 4.90 in phase, whose optimum is that slip (model.md 7.3). Started at A with it (7.4), the run at lambda = 4.85 shakes down (live, o) where OA slips (pinned, x).",
        scene: Scene::Compare {
            pinned: (4.85, 0.0, "OA"),
            live: (4.85, 0.0, "optimal"),
        },
    },
    Stop {
        title: "point B, non-monotonic ratchetting",
        caption: "Point B of Fig. 3 (lambda = 7, phi = 0): every node slips each cycle and the disc turns forward by the same net amount everywhere (model.md 6.2, 8: Fig. 5). Some regions slip forward once a cycle; others alternate forward and backward, the colours of the slip map.",
        scene: Scene::Case {
            load_factor: 7.0,
            phase: 0.0,
            initial: "OA",
            pause_at: None,
        },
    },
    Stop {
        title: "point C, monotonic ratchetting",
        caption: "Point C of Fig. 6 (lambda = 5.1, phi = pi/2): each cycle one slip zone forms near theta = -3 pi/4, splits in two, and the two zones travel round and merge near theta = pi/4 (model.md 8: Fig. 7). No node ever slips against the ratchet: all slip is forward.",
        scene: Scene::Case {
            load_factor: 5.1,
            phase: HALF_PI,
            initial: "OA",
            pause_at: None,
        },
    },
    Stop {
        title: "the sharp change at phi = pi/2",
        caption: "Out of phase there is no history-dependent range: lambda_1 = lambda_2 = lambda_3, about 5 (model.md 8: Fig. 8). At lambda = 4.9 the disc shakes down (pinned, x); at 5.1 it ratchets monotonically (live, o), and W is the same for every transient.",
        scene: Scene::Compare {
            pinned: (4.9, HALF_PI, "OA"),
            live: (5.1, HALF_PI, "OA"),
        },
    },
    Stop {
        title: "the regime map",
        caption: "The paper's figures are lines through this map: the steady state over (lambda, phi) for the transient OA, with lambda_2(phi) of the linear programme drawn over it (model.md 7.3, 8). It fills in as its runs finish; Esc keeps it and gives you the keys.",
        scene: Scene::Regime,
    },
];

/// Where the tour is.
#[derive(Debug, Clone, PartialEq)]
pub struct Tour {
    /// Index of the stop on screen in [`STOPS`].
    pub stop: usize,
    /// A compare stop waiting for its first run's steady state: the case
    /// to open once that run is pinned.
    pending: Option<(f64, f64, &'static str)>,
}

impl App {
    /// The tour's actions; false if `action` is not one.
    pub(super) fn tour_action(&mut self, action: Action) -> bool {
        match action {
            Action::Tour => self.start_tour(),
            Action::TourNext => self.tour_move(1),
            Action::TourPrevious => self.tour_move(-1),
            Action::TourLeave if self.help => self.help = false,
            Action::TourLeave => {
                self.tour = None;
                self.notice = Some("the tour is over: the case is yours".into());
            }
            _ => return false,
        }
        true
    }

    /// Start the tour at its first stop (`--tour`, or `T`). Its stops are
    /// the paper's elliptical cycles: a polyline cycle (`--cycle`) gives
    /// way to the default case's cycle.
    pub fn start_tour(&mut self) {
        if self.case.cycle().as_polyline().is_some() {
            if let Ok(case) = Case::from_params(&crate::tui::default_params()) {
                if let Err(e) = self.case.set_cycle(case.cycle().clone()) {
                    self.notice = Some(e.to_string());
                }
            }
        }
        self.go_to_stop(0);
    }

    /// The tour's stop on screen, with its index, while the tour has the
    /// keys.
    pub fn tour(&self) -> Option<(usize, &'static Stop)> {
        self.tour.as_ref().map(|t| (t.stop, &STOPS[t.stop]))
    }

    fn tour_move(&mut self, delta: isize) {
        let Some(t) = &self.tour else {
            return;
        };
        let to = t.stop.saturating_add_signed(delta).min(STOPS.len() - 1);
        if to == t.stop {
            self.notice = Some(if delta > 0 {
                "the last stop: Esc takes over".into()
            } else {
                "the first stop".into()
            });
            return;
        }
        self.go_to_stop(to);
    }

    fn go_to_stop(&mut self, stop: usize) {
        self.help = false;
        self.log_view.log_open = false;
        self.stepping.pinned = None;
        self.pause_regime();
        self.stepping.pause_on_events = false;
        self.log_view.filter = Filter::default();
        let mut pending = None;
        match STOPS[stop].scene {
            Scene::Case {
                load_factor,
                phase,
                initial,
                pause_at,
            } => {
                self.open_named(load_factor, phase, initial);
                if let Some(n) = pause_at {
                    self.log_view.filter = Filter {
                        kind: Some(EventKind::AdvancingStick),
                        min_nodes: n,
                    };
                    self.stepping.pause_on_events = true;
                }
            }
            Scene::Compare { pinned, live } => {
                self.open_named(pinned.0, pinned.1, pinned.2);
                self.run_to_steady();
                pending = Some(live);
            }
            Scene::Regime => {
                self.open_named(5.0, 0.0, "OA");
                self.stepping.running = false;
                if let Ok(r) = &mut self.regime_view.regime {
                    r.set_initial(Initial::Direct, false);
                }
                self.toggle_regime();
            }
        }
        self.send_filter();
        self.tour = Some(Tour { stop, pending });
        // The caption says where the tour is; the footer gives its keys.
        self.notice = None;
    }

    /// Open a case of the tour in the stepping view, running.
    fn open_named(&mut self, load_factor: f64, phase: f64, initial: &str) {
        let parsed = if initial == "optimal" {
            Ok(Initial::Optimal)
        } else {
            Initial::parse(initial)
        };
        match parsed {
            Ok(i) => self.open_case(load_factor, phase, i),
            Err(e) => self.notice = Some(format!("tour: {e}")),
        }
    }

    fn run_to_steady(&mut self) {
        self.stepping.running = false;
        self.stepping.cursor = None;
        self.stepping.goal = Some(Goal::Steady);
    }

    /// The run stopped by itself (its goal reached, or ended): a compare
    /// stop pins its first run and opens the second.
    pub(super) fn tour_run_stopped(&mut self) {
        let Some(live) = self.tour.as_mut().and_then(|t| t.pending.take()) else {
            return;
        };
        self.pin();
        self.open_named(live.0, live.1, live.2);
        self.run_to_steady();
        self.notice = Some("pinned the first run; the second runs to its steady state".into());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stop_is_a_valid_case_with_a_short_caption() {
        assert_eq!(STOPS.len(), 8);
        for s in &STOPS {
            let sentences = s.caption.matches(". ").count() + 1;
            assert!((2..=4).contains(&sentences), "{}", s.title);
            assert!(s.caption.contains("model.md"), "{}", s.title);
            let names: Vec<&str> = match s.scene {
                Scene::Case { initial, .. } => vec![initial],
                Scene::Compare { pinned, live } => vec![pinned.2, live.2],
                Scene::Regime => vec![],
            };
            for n in names {
                assert!(n == "optimal" || Initial::parse(n).is_ok(), "{n}");
            }
        }
    }
}
