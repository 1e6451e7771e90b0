//! What [`prove_all_levels`] checks after the search, so that the command
//! cannot print "proved" for a product it did not fully explore: every face
//! of levels `0..=`[`COVERED_LEVELS`]'s end runs along explored
//! transitions, and the explored product is the committed listing.

#[allow(clippy::wildcard_imports)]
use super::*;

/// The levels whose every face [`certify`] runs through the explored graph.
pub const COVERED_LEVELS: u32 = 8;

/// `docs/results/all_levels_product.txt`, the product as committed: the
/// lines starting with `S` are [`AllLevelsReport::listing`]'s.
pub const COMMITTED_LISTING: &str = include_str!("../../../../docs/results/all_levels_product.txt");

/// Turns a search's `Proved` into `Failed` unless
///
/// 1. every face of levels `0..=`[`COVERED_LEVELS`], run through both
///    transducers ([`Machine::run_on_point`] at its representative), starts
///    in an explored start state and reads only explored transitions (so
///    the search skipped nothing a real point uses), with equal digits, and
/// 2. for the crate's version 2 walk, the explored states and transitions
///    are, line for line, those of `listing` (the committed
///    `docs/results/all_levels_product.txt`, [`COMMITTED_LISTING`]); the
///    first difference is reported.
///
/// Other verdicts are returned unchanged.
#[must_use]
pub fn certify(machine: &Machine, mut report: AllLevelsReport, listing: &str) -> AllLevelsReport {
    if report.verdict != Verdict::Proved {
        return report;
    }
    if let Err(why) = check_faces(machine, &report) {
        report.verdict = Verdict::Failed(ModelError(why));
        return report;
    }
    if report.walk == Some(WalkVersion::Version2) {
        if let Err(why) = check_listing(&report, listing) {
            report.verdict = Verdict::Failed(ModelError(why));
        }
    }
    report
}

/// Condition 1 of [`certify`].
fn check_faces(machine: &Machine, report: &AllLevelsReport) -> Result<(), String> {
    let ids: HashMap<ProductState, usize> = report
        .product_states
        .iter()
        .enumerate()
        .map(|(id, state)| (*state, id))
        .collect();
    let edges: HashMap<(usize, Column), usize> = report
        .transitions
        .iter()
        .map(|t| ((t.from, t.column), t.to))
        .collect();
    for n in 0..=COVERED_LEVELS {
        let level = Level::new(n).map_err(|e| e.to_string())?;
        for face in crate::lattice::faces(level) {
            let run = machine
                .run_on_point(
                    u128::from(face.x),
                    u128::from(face.y),
                    face.scale_log2(),
                    level,
                )
                .map_err(|e| format!("face {face:?}: {e}"))?;
            let not_explored = |what: String| {
                format!(
                    "the search did not explore the whole product: the face at ({}, {}) / 2^{} \
                     of level {n} {what}",
                    face.x,
                    face.y,
                    face.scale_log2()
                )
            };
            let mut id = match ids.get(&run.states[0]) {
                Some(&id) if report.starts.get(id).copied().flatten().is_some() => id,
                _ => {
                    return Err(not_explored(
                        "starts in a state that is not an explored start".into(),
                    ))
                }
            };
            for (k, column) in run.columns.iter().enumerate() {
                let Some(&to) = edges.get(&(id, *column)) else {
                    return Err(not_explored(format!(
                        "reads the unexplored transition S{id} --[{column}]--> (digit {})",
                        k + 1
                    )));
                };
                if report.product_states[to] != run.states[k + 1] {
                    return Err(not_explored(format!(
                        "leaves transition S{id} --[{column}]"
                    )));
                }
                id = to;
            }
            if run.walk_index != run.reference_index {
                return Err(format!(
                    "face {face:?}: walk {} and reference {} differ on explored transitions",
                    run.walk_index, run.reference_index
                ));
            }
        }
    }
    Ok(())
}

/// Condition 2 of [`certify`].
fn check_listing(report: &AllLevelsReport, listing: &str) -> Result<(), String> {
    let committed: Vec<&str> = listing.lines().filter(|l| l.starts_with('S')).collect();
    let explored = report.listing();
    let differ = |line: usize, committed: Option<&&str>, explored: Option<&String>| {
        format!(
            "the explored product differs from the committed docs/results/all_levels_product.txt \
             ({} lines committed, {} explored); first difference at product line {}: committed \
             {:?}, explored {:?} (if the change is intended, regenerate the file with `prove \
             --all-levels --list` and explain it in docs/verification.md)",
            committed_len(listing),
            explored_len(report),
            line + 1,
            committed.copied().unwrap_or("(none)"),
            explored.map_or("(none)", String::as_str)
        )
    };
    for line in 0..committed.len().max(explored.len()) {
        if committed.get(line).copied() != explored.get(line).map(String::as_str) {
            return Err(differ(line, committed.get(line), explored.get(line)));
        }
    }
    Ok(())
}

fn committed_len(listing: &str) -> usize {
    listing.lines().filter(|l| l.starts_with('S')).count()
}

fn explored_len(report: &AllLevelsReport) -> usize {
    report.product_states.len() + report.transitions.len()
}
