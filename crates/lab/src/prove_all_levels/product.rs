//! The two transducers together: the product machine, its states and
//! starts, and runs on single points.

#[allow(clippy::wildcard_imports)]
use super::*;

/// Why the construction could not be carried out (a bug in a transducer
/// or an assumption of the method that does not hold).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelError(pub String);

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ModelError {}

/// A state of the product: checker, walk and reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ProductState {
    /// The remainders after the columns read so far.
    pub rest: Rest,
    /// The walk transducer.
    pub walk: WalkState,
    /// The reference transducer.
    pub reference: ReferenceState,
}

/// The first column (the integer bits) with its rest, and the reference's
/// guess: what a run starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Start {
    /// Integer bits of `u`, `v`, `w` and the rest after them.
    pub column: Column,
    /// The guessed decremented coordinate.
    pub decremented: Option<usize>,
}

/// The two transducers: the walk's step (the crate's, or a mutated one in
/// tests), the reference's column table and its cell rule (both from the
/// reference's code: [`verify_columns`], [`derive_cell_rule`]).
#[derive(Clone, Copy)]
pub struct Machine {
    step: SymbolicStep,
    columns: ReferenceColumns,
    rule: CellRule,
    pub(super) version: Option<WalkVersion>,
}

impl fmt::Debug for Machine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Machine")
            .field("version", &self.version)
            .field("columns", &self.columns)
            .finish_non_exhaustive()
    }
}

impl Machine {
    /// The machine for one of the crate's walks.
    pub fn new(version: WalkVersion) -> Result<Machine, ModelError> {
        let step = match version {
            WalkVersion::Version2 => step_version2 as SymbolicStep,
            WalkVersion::Version1 => step_version1 as SymbolicStep,
        };
        let columns = ReferenceColumns::learn().map_err(ModelError)?;
        verify_columns(&columns).map_err(ModelError)?;
        let rule = derive_cell_rule(REFERENCE_CELL, REFERENCE_DIAGONAL).map_err(ModelError)?;
        Ok(Machine {
            step,
            columns,
            rule,
            version: Some(version),
        })
    }

    /// A machine with parts replaced (to show that the search rejects a
    /// wrong transducer); it has no real walk to check counterexamples with.
    #[must_use]
    pub fn with_parts(step: SymbolicStep, columns: ReferenceColumns, rule: CellRule) -> Machine {
        Machine {
            step,
            columns,
            rule,
            version: None,
        }
    }

    /// The learnt reference columns.
    #[must_use]
    pub fn columns(&self) -> ReferenceColumns {
        self.columns
    }

    /// The reference's cell rule, derived from its code.
    #[must_use]
    pub fn rule(&self) -> CellRule {
        self.rule
    }

    /// The state a run starts in, or an error if the reference's cell
    /// would not fit the grid (its top column must be all zero).
    pub fn start(&self, start: Start) -> Result<ProductState, ModelError> {
        let Column { bits, rest } = start.column;
        let u_zero = !bits[U] && rest.zero[U];
        let w_zero = !bits[W] && rest.zero[W];
        let reference = ReferenceState {
            parity: false,
            decremented: start.decremented,
            u_zero,
            w_zero,
        };
        if effective_bits(&reference, start.column).iter().any(|&b| b) {
            return Err(ModelError(format!(
                "start {start:?}: the reference's cell has a bit at 2^level"
            )));
        }
        let root = |ru, rv, bit: bool| Symbolic {
            form: Form {
                ru,
                rv,
                constant: i32::from(bit),
            },
            // Not compared before the first step sets the input.
            input: StepInput {
                sum: rest.sum,
                next: start.column,
            },
        };
        let walk = Walk::new(root(1, 0, bits[U]), root(0, 1, bits[V]));
        Ok(ProductState {
            rest,
            walk: WalkState {
                u: walk.u.form,
                v: walk.v.form,
                w: walk.w.form,
                mid_flip: walk.mid_flip,
                top_flip: walk.top_flip,
            },
            reference,
        })
    }

    /// Whether a run in `state` may end its level here: the reference's
    /// guess is the right one for this rest.
    #[must_use]
    pub fn level_may_end(&self, state: &ReferenceState, rest: Rest) -> bool {
        self.rule.outcome(rest, state.u_zero, state.w_zero)
            == CellOutcome::Decrement(state.decremented)
    }

    /// One column: the walk's digit, the reference's digit and the next
    /// state. The column must be admitted by `state.rest` (not checked
    /// here).
    pub fn transition(
        &self,
        state: &ProductState,
        column: Column,
    ) -> Result<(u8, u8, ProductState), ModelError> {
        let input = StepInput {
            sum: state.rest.sum,
            next: column,
        };
        let fail = |why: &str| ModelError(format!("{state:?} column {column:?}: {why}"));
        let s = &state.walk;
        let symbolic = |form| Symbolic { form, input };
        let mut walk = Walk {
            u: symbolic(s.u),
            v: symbolic(s.v),
            w: symbolic(s.w),
            mid_flip: s.mid_flip,
            top_flip: s.top_flip,
        };
        UNDECIDED.with(|flag| flag.set(false));
        let walk_digit = (self.step)(&mut walk);
        if UNDECIDED.with(std::cell::Cell::get) {
            return Err(fail(
                "the step compared a form that is not a single remainder",
            ));
        }
        let advance = |x: Symbolic| {
            x.form
                .advance(column.bits)
                .filter(|f| {
                    f.ru.abs() <= 1 && f.rv.abs() <= 1 && f.constant.abs() <= CONSTANT_BOUND
                })
                .ok_or_else(|| fail(&format!("step result {:?} leaves the finite set", x.form)))
        };
        let walk_state = WalkState {
            u: advance(walk.u)?,
            v: advance(walk.v)?,
            w: advance(walk.w)?,
            mid_flip: walk.mid_flip,
            top_flip: walk.top_flip,
        };
        let effective = effective_bits(&state.reference, column);
        let (reference_digit, parity) = self.columns.digit(state.reference.parity, effective);
        Ok((
            walk_digit,
            reference_digit,
            ProductState {
                rest: column.rest,
                walk: walk_state,
                reference: ReferenceState {
                    parity,
                    ..state.reference
                },
            },
        ))
    }

    /// Runs both transducers on the dyadic point `(x, y) / 2^scale_log2`
    /// at `level`, with the annotations computed from the point: the
    /// automaton's answer for that point. Returns the two indices and the
    /// product states visited (after the start and after each column).
    ///
    /// ```
    /// use micromap_index_lab::prove::WalkVersion;
    /// use micromap_index_lab::prove_all_levels::Machine;
    /// use micromap_index::Level;
    /// let machine = Machine::new(WalkVersion::Version2).unwrap();
    /// // The vertex (1/4, 1/4) at level 2 (scale 4): index 5 by both.
    /// let run = machine.run_on_point(1, 1, 2, Level::new(2).unwrap()).unwrap();
    /// assert_eq!((run.walk_index, run.reference_index), (5, 5));
    /// ```
    pub fn run_on_point(
        &self,
        x: u128,
        y: u128,
        scale_log2: u32,
        level: Level,
    ) -> Result<PointRun, ModelError> {
        let columns = point_columns(x, y, scale_log2, level.get())?;
        let n = level.get() as usize;
        let at_level = columns[n].rest;
        let first = columns[0];
        // The guess a correct run makes: the rule at the level's rest.
        let u_zero = !first.bits[U] && first.rest.zero[U];
        let w_zero = !first.bits[W] && first.rest.zero[W];
        let CellOutcome::Decrement(decremented) = self.rule.outcome(at_level, u_zero, w_zero)
        else {
            return Err(ModelError(format!(
                "the cell rule has no outcome for the point's level end {at_level:?}"
            )));
        };
        let mut state = self.start(Start {
            column: first,
            decremented,
        })?;
        let mut states = vec![state];
        let start_column = first;
        let (mut walk_index, mut reference_index) = (0u64, 0u64);
        for &column in &columns[1..=n] {
            if !state.rest.admits(column.bits, column.rest) {
                return Err(ModelError(format!(
                    "checker rejects the point's own column {column:?}"
                )));
            }
            let (walk_digit, reference_digit, next) = self.transition(&state, column)?;
            walk_index = walk_index << 2 | u64::from(walk_digit);
            reference_index = reference_index << 2 | u64::from(reference_digit);
            state = next;
            states.push(state);
        }
        if !self.level_may_end(&state.reference, state.rest) {
            return Err(ModelError(
                "the rule's own guess fails at the level end".into(),
            ));
        }
        Ok(PointRun {
            walk_index,
            reference_index,
            start: Start {
                column: start_column,
                decremented,
            },
            columns: columns[1..=n].to_vec(),
            states,
        })
    }
}

/// What [`Machine::run_on_point`] computes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PointRun {
    /// The index from the walk transducer's digits.
    pub walk_index: u64,
    /// The index from the reference transducer's digits.
    pub reference_index: u64,
    /// The start the run begins from (its first column and guess).
    pub start: Start,
    /// The columns `1..=n` the run read, one per digit.
    pub columns: Vec<Column>,
    /// The product states of the run, start first (one more than
    /// `columns`).
    pub states: Vec<ProductState>,
}

/// The annotated columns `0..=m` of `(x, y) / 2^scale_log2`, `m` raised to
/// `level` if smaller; the point must be in the closed triangle and `m <=
/// 120`.
fn point_columns(x: u128, y: u128, scale_log2: u32, level: u32) -> Result<Vec<Column>, ModelError> {
    let m = scale_log2.max(level);
    if m > 120 {
        return Err(ModelError(format!("scale 2^{m} is above 2^120")));
    }
    let shift = m - scale_log2;
    let (x, y) = (x << shift, y << shift);
    let one = 1u128 << m;
    if !matches!(x.checked_add(y), Some(sum) if sum <= one) {
        return Err(ModelError(format!(
            "({x}, {y}) / 2^{m} is outside the triangle"
        )));
    }
    let z = one - x - y;
    let values = [x, y, z];
    Ok((0..=m)
        .map(|k| {
            let below = m - k;
            let mask = (1u128 << below) - 1;
            let rem = values.map(|value| value & mask);
            Column {
                bits: values.map(|value| (value >> below) & 1 == 1),
                rest: Rest {
                    sum: ((rem[0] + rem[1] + rem[2]) >> below) as u8,
                    zero: rem.map(|r| r == 0),
                },
            }
        })
        .collect())
}
