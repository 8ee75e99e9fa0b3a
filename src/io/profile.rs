//! The fretting profile as CSV (`run --profile FILE`): the case's metadata
//! header, then one row per node (model.md section 4.1).

use std::fmt::Write;

use crate::analysis::case::Case;
use crate::analysis::profile::Profile;
use crate::stepping::Outcome;

use super::csv::case_metadata;

/// The column header of a profile file.
pub const PROFILE_HEADER: &str =
    "theta,p_min,p_max,q_min,q_max,slip_amplitude,slip_accumulated,dissipation,ruiz,wear";

/// The profile of `case` (started on `initial`), with the verdict it came
/// to, as CSV text: metadata, the column header, one row per node.
pub fn profile_csv(case: &Case, initial: &str, summary: &Outcome, profile: &Profile) -> String {
    let mut m = case_metadata("profile", case, initial);
    m.push("state", summary.state())
        .push("cycle", profile.cycle)
        .push("dissipation", profile.total_dissipation());
    let mut out = m.preamble(PROFILE_HEADER);
    out.push('\n');
    for j in 0..profile.theta.len() {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{}",
            profile.theta[j],
            profile.p_min[j],
            profile.p_max[j],
            profile.q_min[j],
            profile.q_max[j],
            profile.slip_amplitude[j],
            profile.slip_accumulated[j],
            profile.dissipation[j],
            profile.ruiz[j],
            profile.wear[j],
        );
    }
    out
}
