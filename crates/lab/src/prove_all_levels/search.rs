//! The search: liveness of the reference's guesses, the breadth-first
//! exploration of the product, and the completion of a differing column
//! to a counterexample.

#[allow(clippy::wildcard_imports)]
use super::*;

/// The reference's guess state without the parity (which does not affect
/// whether a level can end).
type Guess = (Rest, Option<usize>, bool, bool);

/// Checker states from which the accepting state is reachable.
pub(super) fn completable() -> BTreeSet<Rest> {
    let mut done: BTreeSet<Rest> = [Rest::DONE].into();
    loop {
        let before = done.len();
        for rest in Rest::all() {
            if !done.contains(&rest)
                && bit_triples().any(|bits| {
                    Rest::all().any(|next| done.contains(&next) && rest.admits(bits, next))
                })
            {
                done.insert(rest);
            }
        }
        if done.len() == before {
            return done;
        }
    }
}

/// The columns a state may read next whose rest can still be completed.
fn columns_after(rest: Rest, completable: &BTreeSet<Rest>) -> Vec<Column> {
    bit_triples()
        .flat_map(|bits| Rest::all().map(move |next| Column { bits, rest: next }))
        .filter(|column| {
            completable.contains(&column.rest) && rest.admits(column.bits, column.rest)
        })
        .collect()
}

/// The guess states from which a level end (the rule holds and the rest is
/// completable) is reachable, and a shortest continuation for each.
struct Liveness {
    /// For each live guess state: the columns to a level end (empty if it
    /// may end now).
    to_end: BTreeMap<Guess, Vec<Column>>,
}

impl Liveness {
    fn build(machine: &Machine, completable: &BTreeSet<Rest>) -> Liveness {
        let guesses: Vec<Guess> = completable
            .iter()
            .flat_map(|&rest| {
                [None, Some(U), Some(V), Some(W)]
                    .into_iter()
                    .flat_map(move |g| {
                        [(false, false), (false, true), (true, false), (true, true)]
                            .map(|(uz, wz)| (rest, g, uz, wz))
                    })
            })
            .collect();
        let may_end = |&(rest, g, u_zero, w_zero): &Guess| {
            let state = ReferenceState {
                parity: false,
                decremented: g,
                u_zero,
                w_zero,
            };
            machine.level_may_end(&state, rest)
        };
        let mut to_end: BTreeMap<Guess, Vec<Column>> = guesses
            .iter()
            .filter(|g| may_end(g))
            .map(|&g| (g, Vec::new()))
            .collect();
        // Backward breadth-first: each round adds the states one column
        // further from an end, so the recorded continuations are shortest.
        loop {
            let mut added = Vec::new();
            for &guess in &guesses {
                if to_end.contains_key(&guess) {
                    continue;
                }
                let (rest, g, uz, wz) = guess;
                if let Some((column, tail)) = columns_after(rest, completable)
                    .into_iter()
                    .find_map(|c| to_end.get(&(c.rest, g, uz, wz)).map(|t| (c, t)))
                {
                    let mut path = vec![column];
                    path.extend_from_slice(tail);
                    added.push((guess, path));
                }
            }
            if added.is_empty() {
                return Liveness { to_end };
            }
            to_end.extend(added);
        }
    }

    fn is_live(&self, state: &ProductState) -> bool {
        let r = &state.reference;
        self.to_end
            .contains_key(&(state.rest, r.decremented, r.u_zero, r.w_zero))
    }
}

/// How a product state was first reached.
#[derive(Clone, Copy)]
enum Parent {
    Start(Start),
    Column(usize, Column),
}

/// Explores the product of the walk and reference transducers for one of
/// the crate's walks. `Verdict::Proved` means: for every level `n` and
/// every real point of the closed triangle, the walk equals the reference
/// (see the module docs for what is restated and how it is checked).
pub fn prove_all_levels(version: WalkVersion) -> Result<AllLevelsReport, ModelError> {
    let machine = Machine::new(version)?;
    Ok(certify(&machine, explore(&machine), COMMITTED_LISTING))
}

/// Explores the product for any machine (also a mutated one). This is the
/// search alone: [`prove_all_levels`] also [`certify`]s what it explored.
#[must_use]
pub fn explore(machine: &Machine) -> AllLevelsReport {
    explore_pruned(machine, |_, _| false)
}

/// [`explore`] with a hook that may skip columns the search would follow
/// (`prune(state, column)` true: not explored). Only for showing that an
/// over-pruning search is caught by [`certify`]; [`explore`] prunes nothing.
#[doc(hidden)]
#[must_use]
pub fn explore_pruned(
    machine: &Machine,
    prune: impl Fn(&ProductState, &Column) -> bool,
) -> AllLevelsReport {
    let completable = completable();
    let liveness = Liveness::build(machine, &completable);
    let mut ids: HashMap<ProductState, usize> = HashMap::new();
    let mut states: Vec<ProductState> = Vec::new();
    let mut parents: Vec<Parent> = Vec::new();
    let mut queue = VecDeque::new();
    let mut counts = StateCounts {
        checker: completable.len(),
        live_guesses: liveness.to_end.len(),
        ..StateCounts::default()
    };
    let mut transitions: Vec<Transition> = Vec::new();
    let finish = |counts: StateCounts,
                  states: &[ProductState],
                  parents: &[Parent],
                  transitions: Vec<Transition>,
                  verdict| {
        let walks: HashSet<WalkState> = states.iter().map(|s| s.walk).collect();
        let references: HashSet<ReferenceState> = states.iter().map(|s| s.reference).collect();
        let mut walk_states: Vec<WalkState> = walks.into_iter().collect();
        walk_states.sort();
        AllLevelsReport {
            walk: machine.version,
            counts: StateCounts {
                walk: walk_states.len(),
                reference: references.len(),
                product: states.len(),
                ..counts
            },
            verdict,
            walk_states,
            product_states: states.to_vec(),
            transitions,
            starts: parents
                .iter()
                .map(|p| match p {
                    Parent::Start(start) => Some(*start),
                    Parent::Column(..) => None,
                })
                .collect(),
        }
    };
    for bits in bit_triples() {
        for rest in Rest::all() {
            let ones = bits.iter().filter(|&&b| b).count() as u8;
            if ones + rest.sum != 1 || !completable.contains(&rest) {
                continue;
            }
            for decremented in [None, Some(U), Some(V), Some(W)] {
                let start = Start {
                    column: Column { bits, rest },
                    decremented,
                };
                let u_zero = !bits[U] && rest.zero[U];
                let w_zero = !bits[W] && rest.zero[W];
                if !liveness
                    .to_end
                    .contains_key(&(rest, decremented, u_zero, w_zero))
                {
                    continue;
                }
                counts.starts += 1;
                let state = match machine.start(start) {
                    Ok(state) => state,
                    Err(e) => {
                        return finish(counts, &states, &parents, transitions, Verdict::Failed(e))
                    }
                };
                if let std::collections::hash_map::Entry::Vacant(slot) = ids.entry(state) {
                    slot.insert(states.len());
                    queue.push_back(states.len());
                    states.push(state);
                    parents.push(Parent::Start(start));
                }
            }
        }
    }
    while let Some(id) = queue.pop_front() {
        let state = states[id];
        for column in columns_after(state.rest, &completable) {
            let probe = ProductState {
                rest: column.rest,
                ..state
            };
            if !liveness.is_live(&probe) || prune(&state, &column) {
                continue; // no valid word goes on from here to a level end
            }
            counts.transitions += 1;
            let (walk_digit, reference_digit, next) = match machine.transition(&state, column) {
                Ok(step) => step,
                Err(e) => {
                    let path = path_to(&parents, id);
                    let why = format!("{e}; reached by {}", describe_path(&path, column));
                    let verdict = Verdict::Failed(ModelError(why));
                    return finish(counts, &states, &parents, transitions, verdict);
                }
            };
            if walk_digit != reference_digit {
                let verdict = counterexample(
                    machine,
                    &liveness,
                    &completable,
                    &parents,
                    id,
                    column,
                    &next,
                );
                return finish(counts, &states, &parents, transitions, verdict);
            }
            let to = *ids.entry(next).or_insert_with(|| {
                queue.push_back(states.len());
                states.push(next);
                parents.push(Parent::Column(id, column));
                states.len() - 1
            });
            transitions.push(Transition {
                from: id,
                column,
                walk_digit,
                reference_digit,
                to,
            });
        }
    }
    finish(counts, &states, &parents, transitions, Verdict::Proved)
}

/// The start and the columns that first reached state `id`.
fn path_to(parents: &[Parent], mut id: usize) -> (Start, Vec<Column>) {
    let mut columns = Vec::new();
    loop {
        match parents[id] {
            Parent::Start(start) => {
                columns.reverse();
                return (start, columns);
            }
            Parent::Column(parent, column) => {
                columns.push(column);
                id = parent;
            }
        }
    }
}

fn describe_path((start, columns): &(Start, Vec<Column>), last: Column) -> String {
    let bits = |b: [bool; 3]| {
        b.map(|x| char::from(b'0' + u8::from(x)))
            .iter()
            .collect::<String>()
    };
    let mut text = format!(
        "start {} guess {:?}",
        bits(start.column.bits),
        start.decremented
    );
    for column in columns.iter().chain([&last]) {
        text.push(' ');
        text.push_str(&bits(column.bits));
    }
    text
}

/// Completes the differing column to a point and a level, and recomputes
/// it with the transducers and the real functions.
fn counterexample(
    machine: &Machine,
    liveness: &Liveness,
    completable: &BTreeSet<Rest>,
    parents: &[Parent],
    id: usize,
    column: Column,
    next: &ProductState,
) -> Verdict {
    let (start, mut columns) = path_to(parents, id);
    columns.push(column);
    let r = &next.reference;
    let Some(to_end) = liveness
        .to_end
        .get(&(next.rest, r.decremented, r.u_zero, r.w_zero))
    else {
        return Verdict::Failed(ModelError("a live state has no way to a level end".into()));
    };
    columns.extend_from_slice(to_end);
    let level = columns.len() as u32;
    // Then finish the digits of the point: a shortest way to nothing left.
    let mut rest = columns.last().map_or(start.column.rest, |c| c.rest);
    while rest != Rest::DONE {
        let Some(step) = columns_after(rest, completable)
            .into_iter()
            .min_by_key(|c| distance_to_done(c.rest, completable))
        else {
            return Verdict::Failed(ModelError("a completable rest cannot be completed".into()));
        };
        columns.push(step);
        rest = step.rest;
    }
    let m = columns.len() as u32;
    let value = |c: usize| {
        std::iter::once(start.column)
            .chain(columns.iter().copied())
            .fold(0u128, |acc, col| acc << 1 | u128::from(col.bits[c]))
    };
    let (x, y, z) = (value(U), value(V), value(W));
    let Ok(level) = Level::new(level) else {
        return Verdict::Failed(ModelError(format!("counterexample at level {level} > 32")));
    };
    if m > 60 || x + y + z != 1u128 << m {
        return Verdict::Failed(ModelError(format!(
            "counterexample ({x}, {y}, {z}) / 2^{m} does not check"
        )));
    }
    let run = match machine.run_on_point(x, y, m, level) {
        Ok(run) => run,
        Err(e) => return Verdict::Failed(e),
    };
    if run.walk_index == run.reference_index {
        return Verdict::Failed(ModelError(format!(
            "the search's counterexample ({x}, {y}) / 2^{m} at level {} agrees when rerun",
            level.get()
        )));
    }
    let face = face_containing(x as u64, y as u64, m, level);
    let real = match machine.version.map(|version| real_indices(version, &face)) {
        Some(Err(e)) => return Verdict::Failed(ModelError(format!("real functions: {e}"))),
        Some(Ok(real)) => Some(real),
        None => None,
    };
    Verdict::Counterexample(Box::new(Counterexample {
        level,
        face,
        point: (x, y, m),
        walk_index: run.walk_index,
        reference_index: run.reference_index,
        real,
    }))
}

/// Columns needed to reach [`Rest::DONE`] (for the shortest completion).
fn distance_to_done(from: Rest, completable: &BTreeSet<Rest>) -> usize {
    let mut frontier = vec![from];
    let mut seen: HashSet<Rest> = [from].into();
    for distance in 0..=completable.len() {
        if frontier.contains(&Rest::DONE) {
            return distance;
        }
        frontier = frontier
            .iter()
            .flat_map(|&rest| columns_after(rest, completable))
            .map(|c| c.rest)
            .filter(|rest| seen.insert(*rest))
            .collect();
    }
    usize::MAX
}
