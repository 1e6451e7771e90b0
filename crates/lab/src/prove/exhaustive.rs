//! Running a level on all cores.

#[allow(clippy::wildcard_imports)]
use super::*;

/// Counts of one unit of work.
#[derive(Clone, Debug, Default)]
pub(super) struct Tally {
    pub(super) faces: u64,
    pub(super) mismatches_by_kind: [u64; 6],
    pub(super) examples: Vec<Mismatch>,
}

impl Tally {
    #[cold]
    #[inline(never)]
    pub(super) fn record_mismatch(
        &mut self,
        level: Level,
        x: u64,
        y: u64,
        walk: u64,
        reference: u64,
        keep: usize,
    ) {
        let kind = FaceKind::at(x, y);
        self.mismatches_by_kind[kind.index()] += 1;
        if self.examples.len() < keep {
            self.examples.push(Mismatch {
                face: Face { level, x, y, kind },
                walk,
                reference,
            });
        }
    }
}

/// The tallies of the units that finished, in unit order, and whether
/// that is all of them.
pub(super) struct Finished {
    pub(super) tallies: Vec<Tally>,
    pub(super) all: bool,
}

/// Runs `unit(i)` for `i in 0..units` on `threads` threads, stopping early
/// when cancelled. Only finished units are stored, so a huge unit count
/// (a sample of `u64::MAX` faces) costs no memory up front.
pub(super) fn run_units(
    units: u64,
    threads: usize,
    progress: &Progress,
    unit: impl Fn(u64) -> Tally + Sync,
) -> Finished {
    progress.start(units);
    let next = AtomicU64::new(0);
    let finished: Mutex<Vec<(u64, Tally)>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads.max(1) {
            scope.spawn(|| loop {
                if progress.is_cancelled() {
                    break;
                }
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= units {
                    break;
                }
                let tally = unit(i);
                if let Ok(mut finished) = finished.lock() {
                    finished.push((i, tally));
                }
                progress.finish_unit();
            });
        }
    });
    let mut finished = finished
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    finished.sort_unstable_by_key(|&(i, _)| i);
    Finished {
        all: finished.len() as u64 == units,
        tallies: finished.into_iter().map(|(_, tally)| tally).collect(),
    }
}

pub(super) fn thread_count(settings: &Settings) -> usize {
    if settings.threads > 0 {
        settings.threads
    } else {
        std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
    }
}

impl Reference {
    /// The reference's integer half on a cell.
    #[inline(always)]
    pub(super) fn index_from_cell(self, cell: spec::Cell, level: Level) -> u64 {
        match self {
            // level <= 16: the cell is at most 2^16 and fits u32.
            Reference::Spec => u64::from(spec::index_from_cell(
                cell.iu as u32,
                cell.iv as u32,
                cell.diagonal,
                level.get(),
            )),
            Reference::SpecWide => {
                spec::wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get())
            }
        }
    }

    /// The reference's index for the point `(x, y) / 2^(level + 2)`.
    pub(super) fn index(self, x: u64, y: u64, level: Level) -> u64 {
        // scale_log2 = level + 2 <= 34 is within cell_dyadic's 62.
        let cell = spec::cell_dyadic(x, y, level.get() + 2, level).expect("scale within 2^62");
        self.index_from_cell(cell, level)
    }
}

pub(super) fn checked_level(level: Level, reference: Reference) -> Result<Level, ProveError> {
    if level.get() > reference.max_level() {
        Err(ProveError::Level(Error::LevelTooHigh {
            level: level.get(),
            max: reference.max_level(),
        }))
    } else {
        Ok(level)
    }
}

/// Depth at which the tree is cut into units of work: 4^6 = 4096 units
/// balance two or more threads and keep cancellation prompt.
pub(super) const UNIT_DEPTH: u32 = 6;

/// Compares the walk with the reference on every face of the level's
/// lattice, on all cores. A complete report with no mismatches and
/// `faces_checked == faces_expected` proves the two equal at every real
/// point of the closed triangle at that level ([`LevelReport::is_proof`]).
pub fn prove_level(
    level: Level,
    settings: &Settings,
    progress: &Progress,
) -> Result<LevelReport, ProveError> {
    let started = Instant::now();
    let level = checked_level(level, settings.reference)?;
    let table = Table::build(settings.walk)?;
    let keep = settings.examples;
    let Some(twig_depth) = level.get().checked_sub(1) else {
        // Level 0: one leaf, the root, checked face by face.
        let root = Node::root(level);
        let mut checker = Checker {
            table: &table,
            level,
            reference: settings.reference,
            keep,
            tally: Tally::default(),
        };
        progress.start(1);
        checker.check_each_face(&root);
        checker.tally.faces = u64::from(OWNED_FACES[usize::from(ALL_OWNED)]);
        progress.finish_unit();
        return Ok(merge(
            empty_report(
                level,
                settings,
                Method::Exhaustive,
                lattice::face_count(level),
            ),
            Finished {
                tallies: vec![checker.tally],
                all: true,
            },
            keep,
            started,
        ));
    };
    let unit_depth = twig_depth.min(UNIT_DEPTH);
    let mut units = Units(Vec::new());
    descend(&table, &Node::root(level), unit_depth, &mut units);
    let units = units.0;
    let below = twig_depth - unit_depth;
    let finished = match settings.reference {
        // `units` has at most 4^UNIT_DEPTH entries: the casts are exact.
        Reference::Spec => run_units(units.len() as u64, thread_count(settings), progress, |i| {
            check_subtree(
                &table,
                &units[i as usize],
                below,
                level,
                Reference::Spec,
                keep,
            )
        }),
        Reference::SpecWide => {
            run_units(units.len() as u64, thread_count(settings), progress, |i| {
                check_subtree(
                    &table,
                    &units[i as usize],
                    below,
                    level,
                    Reference::SpecWide,
                    keep,
                )
            })
        }
    };
    Ok(merge(
        empty_report(
            level,
            settings,
            Method::Exhaustive,
            lattice::face_count(level),
        ),
        finished,
        keep,
        started,
    ))
}

/// A report with nothing counted yet.
pub(super) fn empty_report(
    level: Level,
    settings: &Settings,
    method: Method,
    expected: u128,
) -> LevelReport {
    LevelReport {
        level,
        walk: settings.walk,
        reference: settings.reference,
        method,
        faces_checked: 0,
        faces_expected: expected,
        mismatches_by_kind: [0; 6],
        examples: Vec::new(),
        seconds: 0.0,
        complete: true,
    }
}

/// Collects the nodes it visits: the units of work.
pub(super) struct Units(Vec<Node>);

impl Visitor for Units {
    fn visit(&mut self, node: &Node) {
        self.0.push(*node);
    }
}

/// Compares every face below the twigs it visits with the reference (the
/// hot loop).
///
/// The reference is a function of the face's cell `(iu, iv, diagonal)`
/// ([`spec::cell_dyadic`]) alone, and the faces a leaf owns normally have
/// the cell of its interior. So the integer half runs once per leaf, on the
/// interior, and each other face only has its cell compared with that
/// leaf's; a twig where anything differs is checked again face by face
/// ([`Checker::check_each_face`]), which also reports the mismatches.
pub(super) struct Checker<'t> {
    pub(super) table: &'t Table,
    pub(super) level: Level,
    pub(super) reference: Reference,
    pub(super) keep: usize,
    pub(super) tally: Tally,
}

impl Checker<'_> {
    #[inline(always)]
    pub(super) fn cell_of(&self, [x, y]: [u64; 2]) -> spec::Cell {
        // scale_log2 = level + 2 <= 34 is within cell_dyadic's 62.
        spec::cell_dyadic(x, y, self.level.get() + 2, self.level).expect("scale within 2^62")
    }

    /// Every face of one leaf through the whole reference.
    #[cold]
    #[inline(never)]
    pub(super) fn check_each_face(&mut self, leaf: &Node) {
        for &point in LeafFaces::of(leaf.corners, leaf.owned).as_slice() {
            let expected = self
                .reference
                .index_from_cell(self.cell_of(point), self.level);
            if expected != leaf.index {
                let keep = self.keep;
                self.tally
                    .record_mismatch(self.level, point[0], point[1], leaf.index, expected, keep);
            }
        }
    }
}

impl Visitor for Checker<'_> {
    #[inline(always)]
    fn visit(&mut self, node: &Node) {
        let twig = Twig::new(self.table, node);
        let mut cells = [spec::Cell {
            iu: 0,
            iv: 0,
            diagonal: false,
        }; 4];
        let mut differs = false;
        for (position, cell) in cells.iter_mut().enumerate() {
            *cell = self.cell_of(twig.interior(position));
            let expected = self.reference.index_from_cell(*cell, self.level);
            differs |= expected != twig.leaf_index(position);
        }
        for (position, point) in twig.boundary_faces() {
            let cell = self.cell_of(point);
            let own = cells[position];
            // `&`, not `&&`: no branch on data.
            differs |=
                !((cell.iu == own.iu) && (cell.iv == own.iv) && (cell.diagonal == own.diagonal));
        }
        self.tally.faces += 4 + twig.boundary.len() as u64;
        if differs {
            for position in 0..4 {
                self.check_each_face(&twig.leaf(position));
            }
        }
    }
}

/// Every face below the twigs `depth` levels below `node`, compared with
/// the reference.
#[inline(always)]
pub(super) fn check_subtree(
    table: &Table,
    node: &Node,
    depth: u32,
    level: Level,
    reference: Reference,
    keep: usize,
) -> Tally {
    let mut checker = Checker {
        table,
        level,
        reference,
        keep,
        tally: Tally::default(),
    };
    descend(table, node, depth, &mut checker);
    checker.tally
}

pub(super) fn merge(
    mut report: LevelReport,
    finished: Finished,
    keep: usize,
    started: Instant,
) -> LevelReport {
    report.complete = finished.all;
    for tally in finished.tallies {
        report.faces_checked += u128::from(tally.faces);
        for (total, count) in report
            .mismatches_by_kind
            .iter_mut()
            .zip(tally.mismatches_by_kind)
        {
            *total += u128::from(count);
        }
        let room = keep.saturating_sub(report.examples.len());
        report
            .examples
            .extend(tally.examples.into_iter().take(room));
    }
    report.seconds = started.elapsed().as_secs_f64();
    report
}
