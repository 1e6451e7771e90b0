//! Checking anyone's micromap for one triangle against the texture under
//! the baker's model: every known micro-triangle whose closed (dilated)
//! area can read a texel of the other class is a [`Contradiction`], with an
//! exact witness point where one is found.

use super::alpha_test::{alpha_at, largest_alpha, VertexScale};
use super::baker::Baker;
use super::classify::{is_small, Block, Classes, Grid, Placed};
use super::exact::{ExactTriangle, TexelPoint};
use super::triangle::UvTriangle;
use crate::inverse::micro_triangles;
use crate::micromap::{State, TriangleOpacity};
use crate::Level;
use alloc::vec::Vec;

/// A micro-triangle whose known state the texture contradicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Contradiction {
    /// The micro-triangle's index (0 for a special index).
    pub micro_triangle: u64,
    /// The state the micromap gives it.
    pub state: State,
    /// A point of the closed micro-triangle whose footprint holds a texel of
    /// the other class; under [`Model::GpuBinary32`](crate::bake::Model::GpuBinary32) the footprint of the
    /// point dilated by the model's margin, so the point itself may lie
    /// just outside that texel's own footprint (`None` only if the exact
    /// point search gave up, in which case the block search alone proved
    /// the contradiction).
    pub witness: Option<TexelPoint>,
    /// The texel of the other class in that (dilated) footprint, after
    /// wrapping (`None`: the border colour).
    pub texel: Option<(u32, u32)>,
}

/// What [`Baker::verify`] found for one triangle.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Verification {
    /// Micro-triangles whose known state the texture contradicts.
    pub contradictions: Vec<Contradiction>,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Unknown micro-triangles (nothing to check).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide (neither
    /// confirmed nor contradicted).
    pub undecided: u64,
    /// `false` when the coordinates are not finite or off the exact grid:
    /// then nothing was checked.
    pub checked: bool,
}

/// What [`Baker::verify_each`] counted for one triangle (the contradictions
/// themselves went to its callback).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct VerifyCounts {
    /// Known micro-triangles whose state the texture contradicts (every
    /// one, also those the callback did not keep).
    pub contradictions: u64,
    /// Known micro-triangles checked.
    pub known: u64,
    /// Known micro-triangles past the caller's cap: not checked.
    pub unchecked: u64,
    /// Unknown micro-triangles (nothing to check).
    pub unknown: u64,
    /// Known micro-triangles the block budget could not decide (neither
    /// confirmed nor contradicted).
    pub undecided: u64,
    /// `false` when the coordinates are not finite or off the exact grid:
    /// then nothing was checked.
    pub checked: bool,
}

/// What [`Baker::value_verdict`] found.
enum ValueVerdict {
    /// The filtered value keeps the state everywhere.
    Holds,
    /// It may not, at this texel-space point.
    Contradicted((f64, f64)),
    /// The budget or the split depth ran out first.
    Undecided,
}

/// The most times [`Baker::value_verdict`] halves a micro-triangle: a
/// level-0 triangle over 4096 texels reaches pieces of a texel or two.
const MAX_VALUE_SPLITS: u32 = 12;

/// A value witness's coordinates are multiples of `2^-40` texels (within
/// `2^-40` of the point where the value is lowest or highest).
const VALUE_WITNESS_SHIFT: u32 = 40;

/// `2^VALUE_WITNESS_SHIFT`.
const VALUE_WITNESS_SCALE: f64 = (1u64 << VALUE_WITNESS_SHIFT) as f64;

impl Baker {
    /// Checks another baker's answer for one triangle: every micro-triangle
    /// with a known state (opaque, transparent; a special index counts as a
    /// level-0 map) whose closed area can read a texel of the other class
    /// under this baker's sampler model is a [`Contradiction`], with an
    /// exact witness point. Unknown states are never contradicted.
    ///
    /// This form keeps every contradiction: its memory grows with their
    /// number (about 40 bytes each; a wrong level-16 map can have 2^32).
    /// [`verify_each`](Self::verify_each) hands each one to a callback
    /// instead and caps the work.
    #[must_use]
    pub fn verify(&self, uv: &UvTriangle, opacity: &TriangleOpacity<'_>) -> Verification {
        let mut contradictions = Vec::new();
        let counts = self.verify_each(uv, opacity, u64::MAX, |c| contradictions.push(c));
        Verification {
            contradictions,
            known: counts.known,
            unknown: counts.unknown,
            undecided: counts.undecided,
            checked: counts.checked,
        }
    }

    /// [`verify`](Self::verify) in bounded memory: each contradiction is
    /// passed to `visit` as it is found (keep the first few, count the rest)
    /// and only counts are returned. At most `max_known` known
    /// micro-triangles are checked; the known ones past that cap are
    /// counted in [`VerifyCounts::unchecked`], never silently dropped (a
    /// caller must not call a triangle with `unchecked > 0` sound).
    pub fn verify_each(
        &self,
        uv: &UvTriangle,
        opacity: &TriangleOpacity<'_>,
        max_known: u64,
        visit: impl FnMut(Contradiction),
    ) -> VerifyCounts {
        self.verify_each_alpha((uv, None), opacity, max_known, visit)
    }

    /// [`verify_each`](Self::verify_each) of a triangle whose texture's
    /// alpha is multiplied by its vertex `alphas` when given (only on a
    /// baker made for them, as [`bake_split`](Self::bake_split) says; on
    /// another, every known micro-triangle is undecided).
    pub(crate) fn verify_each_alpha(
        &self,
        (uv, alphas): (&UvTriangle, Option<[f32; 3]>),
        opacity: &TriangleOpacity<'_>,
        max_known: u64,
        mut visit: impl FnMut(Contradiction),
    ) -> VerifyCounts {
        let level = match opacity {
            TriangleOpacity::Micromap(map) => map.level(),
            TriangleOpacity::Special(_) => Level(0),
        };
        let state_of = |index: u64| match opacity {
            TriangleOpacity::Micromap(map) => map.get(index).unwrap_or(State::UnknownOpaque),
            TriangleOpacity::Special(state) => *state,
        };
        let mut report = VerifyCounts::default();
        let Ok((fx, fy, grid)) = self.frames(self.model, uv, level) else {
            return report;
        };
        // With vertex alpha: the alpha at a micro-triangle corner `(a, b)`
        // (of `2^level` per side, as placed: vertex 0 at the origin).
        let vertex = match alphas {
            None => None,
            Some(v) if self.covers(v) => {
                let side = f64::from(1u32 << level.get());
                let largest = largest_alpha(v);
                let v = v.map(f64::from);
                let at = move |c: (u64, u64)| alpha_at(v, side, c);
                Some((at, largest))
            }
            Some(_) => {
                report.checked = true;
                for t in micro_triangles(level) {
                    if state_of(t.index()).is_known() {
                        report.known += 1;
                        report.undecided += 1;
                    } else {
                        report.unknown += 1;
                    }
                }
                return report;
            }
        };
        report.checked = true;
        let mut stack = Vec::new();
        for t in micro_triangles(level) {
            let state = state_of(t.index());
            if !state.is_known() {
                report.unknown += 1;
                continue;
            }
            if report.known >= max_known {
                report.unchecked += 1;
                continue;
            }
            report.known += 1;
            let other = Classes {
                opaque: state == State::Transparent,
                transparent: state == State::Opaque,
            };
            let corners = t.vertices_scaled();
            let alphas = vertex.map(|(at, largest)| (corners.map(at), largest));
            let p = Self::place(&fx, &fy, level.get(), corners);
            let exact = ExactTriangle::new(p.x, p.y);
            // A larger budget than baking: a verdict, not a bake.
            let search = self.classifier.classes.search(
                &exact,
                grid,
                other,
                self.classifier.block_budget.saturating_mul(16),
                &mut stack,
            );
            let witness_block = search.witness_block[usize::from(other.opaque)];
            // Linear filtering by value: texels of the other class are read,
            // but the filtered value may still pass (fail) everywhere; where
            // it does not, the point where it is lowest (highest) is the
            // witness.
            let classes = &self.classifier.classes;
            if witness_block.is_some() && classes.test.by_value {
                let budget = u64::from(self.classifier.block_budget).saturating_mul(16);
                match self.value_verdict(p, (grid, alphas), state, budget) {
                    ValueVerdict::Holds => {}
                    ValueVerdict::Undecided => report.undecided += 1,
                    ValueVerdict::Contradicted(at) => {
                        report.contradictions += 1;
                        let dyadic = |c: f64| (c * VALUE_WITNESS_SCALE) as i128;
                        let floor =
                            |c: f64| i128::from(c as i64 - i64::from((c as i64 as f64) > c));
                        visit(Contradiction {
                            micro_triangle: t.index(),
                            state,
                            witness: Some(TexelPoint {
                                x: dyadic(at.0),
                                shift_x: VALUE_WITNESS_SHIFT,
                                y: dyadic(at.1),
                                shift_y: VALUE_WITNESS_SHIFT,
                            }),
                            texel: classes.wrap(floor(at.0), floor(at.1)),
                        });
                    }
                }
                continue;
            }
            match witness_block {
                Some(found) => {
                    let (block, witness) = self.witness(&exact, found, grid, other.opaque);
                    let texel = witness.map_or_else(
                        || self.classifier.classes.wrap(block.x0, block.y0),
                        |w| {
                            // The witness is on a grid 2^w.2 times finer.
                            let (tx, ty) = self.classifier.classes.footprint_texel_in(
                                block,
                                (w.0, w.1),
                                grid,
                                w.2,
                            );
                            self.classifier.classes.wrap(tx, ty)
                        },
                    );
                    report.contradictions += 1;
                    visit(Contradiction {
                        micro_triangle: t.index(),
                        state,
                        witness: witness.map(|(x, y, extra)| TexelPoint {
                            x,
                            shift_x: fx.shift + extra,
                            y,
                            shift_y: fy.shift + extra,
                        }),
                        texel,
                    });
                }
                None if search.exhausted => report.undecided += 1,
                None => {}
            }
        }
        report
    }

    /// Whether the filtered value (linear filtering by value) keeps `state`
    /// everywhere on the placed micro-triangle `p`, dilated by `grid`'s
    /// margin: pieces whose bounding block is small are judged by
    /// [`region_value`](super::classify::TexelClasses::region_value); larger
    /// ones are split at their edge midpoints on a twice finer grid with
    /// the same margin in texels (the dilated pieces cover the dilated
    /// whole), as the bake's walk splits them, until `budget` cells and
    /// splits are spent or the pieces are [`MAX_VALUE_SPLITS`] levels
    /// down: then [`ValueVerdict::Undecided`]. With vertex alpha (the
    /// corners' exact alphas and the triangle's largest), each piece is
    /// judged by its own range; a piece its range cannot confirm is
    /// contradicted only if the value fails even at the alpha most in the
    /// state's favour over it (so at the witness's own alpha too), and is
    /// otherwise split like a large one (a special index is judged whole,
    /// but was baked in parts: its pieces' alphas are narrower).
    fn value_verdict(
        &self,
        p: Placed<i128>,
        (grid, alphas): (Grid, Option<([f64; 3], f64)>),
        state: State,
        budget: u64,
    ) -> ValueVerdict {
        let classes = &self.classifier.classes;
        let other = |c: Classes| {
            if state == State::Opaque {
                c.transparent
            } else {
                c.opaque
            }
        };
        let mut work = 0u64;
        let mut undecided = false;
        let mut stack = Vec::new();
        let (corners, largest) = alphas.unwrap_or(([0.0; 3], 0.0));
        stack.push((p, corners, grid, 0u32));
        while let Some((p, corners, grid, depth)) = stack.pop() {
            work += 1;
            let block = self.classifier.bounding_block(&p, grid);
            if !other(classes.quick(block)) {
                continue;
            }
            let at_limit = depth == MAX_VALUE_SPLITS || work > budget;
            if is_small(block) {
                let scale = alphas.map(|_| VertexScale::over(corners, largest));
                let r = classes.region_value(&p, grid, scale);
                work += u64::from(r.cells);
                if !other(Classes::of_bits(r.bits)) {
                    continue;
                }
                // Contradicted even at the alpha most in the state's
                // favour (the piece's highest for opaque, lowest for
                // transparent): so at the witness's own alpha too. Else a
                // narrower piece has a narrower alpha: split.
                let favour = scale.map(|s| {
                    let a = if state == State::Opaque { s.hi } else { s.lo };
                    VertexScale { lo: a, hi: a }
                });
                let sure = if favour == scale {
                    r
                } else {
                    classes.region_value(&p, grid, favour)
                };
                if other(Classes::of_bits(sure.bits)) {
                    let at = if state == State::Opaque {
                        sure.argmin
                    } else {
                        sure.argmax
                    };
                    return ValueVerdict::Contradicted(at);
                }
            }
            if at_limit {
                undecided = true;
                continue;
            }
            let finer = Grid {
                shifts: (grid.shifts.0 + 1, grid.shifts.1 + 1),
                margin: (
                    grid.margin.0.map(|m| m.finer(1)),
                    grid.margin.1.map(|m| m.finer(1)),
                ),
            };
            let (x, y) = (p.x.map(|c| 2 * c), p.y.map(|c| 2 * c));
            let mid = |a: usize, b: usize| ((x[a] + x[b]) / 2, (y[a] + y[b]) / 2);
            let (m01, m12, m20) = (mid(0, 1), mid(1, 2), mid(2, 0));
            let v = [(x[0], y[0]), (x[1], y[1]), (x[2], y[2])];
            let c = corners;
            let half = |a: f64, b: f64| (a + b) * 0.5;
            let (a01, a12, a20) = (half(c[0], c[1]), half(c[1], c[2]), half(c[2], c[0]));
            for (piece, alphas) in [
                ([v[0], m01, m20], [c[0], a01, a20]),
                ([m01, v[1], m12], [a01, c[1], a12]),
                ([m20, m12, v[2]], [a20, a12, c[2]]),
                ([m01, m12, m20], [a01, a12, a20]),
            ] {
                let piece = Placed {
                    x: piece.map(|q| q.0),
                    y: piece.map(|q| q.1),
                };
                stack.push((piece, alphas, finer, depth + 1));
            }
        }
        if undecided {
            ValueVerdict::Undecided
        } else {
            ValueVerdict::Holds
        }
    }

    /// A witness for a contradiction: a point of `t` reading a texel of
    /// the class `opaque`, searched in `found` (the block the search
    /// reported) and then in every single texel of that class in `t`'s
    /// footprint (a contact region can be far smaller than the finest grid
    /// of [`witness_in`](Self::witness_in) in one texel and hold a vertex
    /// in another).
    fn witness(
        &self,
        t: &ExactTriangle,
        found: Block,
        grid: Grid,
        opaque: bool,
    ) -> (Block, Option<(i128, i128, u32)>) {
        if let Some(w) = self.witness_in(t, found, grid) {
            return (found, Some(w));
        }
        let b = self.classifier.classes.bounding_block(
            (t.min_x(), t.max_x()),
            (t.min_y(), t.max_y()),
            grid,
        );
        if (b.x1 - b.x0 + 1).saturating_mul(b.y1 - b.y0 + 1) <= 4096 {
            for y in b.y0..=b.y1 {
                for x in b.x0..=b.x1 {
                    let classes = self
                        .classifier
                        .classes
                        .class_of(self.classifier.classes.wrap(x, y));
                    if !(if opaque {
                        classes.opaque
                    } else {
                        classes.transparent
                    }) {
                        continue;
                    }
                    let texel = Block {
                        x0: x,
                        x1: x,
                        y0: y,
                        y1: y,
                    };
                    let [rx0, rx1, ry0, ry1] = self.classifier.classes.block_reach(texel, grid);
                    if !t.meets(rx0, rx1, ry0, ry1) {
                        continue;
                    }
                    if let Some(w) = self.witness_in(t, texel, grid) {
                        return (texel, Some(w));
                    }
                }
            }
        }
        (found, None)
    }

    /// A point of `t` (closed) in the reach of `block`, on a grid `2^extra`
    /// times finer: the block's included corner, a vertex, or a vertex of
    /// a sub-triangle found by subdividing `t` where it meets the reach.
    /// Every contact of a triangle with a half-open rectangle contains one
    /// of these (a 2-D overlap holds fine-grid points; a contact along an
    /// edge holds dyadic points of that edge; a single-point contact is a
    /// vertex or the corner).
    fn witness_in(&self, t: &ExactTriangle, block: Block, grid: Grid) -> Option<(i128, i128, u32)> {
        const EXTRA: u32 = 20;
        let [x0, x1, y0, y1] = self.classifier.classes.block_reach(block, grid);
        let inside = |px: i128, py: i128| x0 <= px && px < x1 && y0 <= py && py < y1;
        if t.contains(x0, y0) {
            return Some((x0, y0, 0));
        }
        for k in 0..3 {
            if inside(t.x[k], t.y[k]) {
                return Some((t.x[k], t.y[k], 0));
            }
        }
        // Finer grid: everything times 2^EXTRA, if it stays in range.
        let limit = 1i128 << 120;
        let up = |c: i128| c.checked_mul(1 << EXTRA).filter(|v| v.abs() < limit);
        let scale3 =
            |c: [i128; 3]| -> Option<[i128; 3]> { Some([up(c[0])?, up(c[1])?, up(c[2])?]) };
        let (rx0, rx1, ry0, ry1) = (up(x0)?, up(x1)?, up(y0)?, up(y1)?);
        let inside_fine = |px: i128, py: i128| rx0 <= px && px < rx1 && ry0 <= py && py < ry1;
        let mut stack = Vec::new();
        stack.push((scale3(t.x)?, scale3(t.y)?, 0u32));
        let mut tests = 0u32;
        while let Some((x, y, depth)) = stack.pop() {
            tests += 1;
            if tests > 1 << 16 {
                return None;
            }
            let sub = ExactTriangle::new(x, y);
            if !sub.meets(rx0, rx1, ry0, ry1) {
                continue;
            }
            for k in 0..3 {
                if inside_fine(x[k], y[k]) {
                    return Some((x[k], y[k], EXTRA));
                }
            }
            if depth == EXTRA {
                continue;
            }
            let mid = |a: usize, b: usize| ((x[a] + x[b]) / 2, (y[a] + y[b]) / 2);
            let (m01, m12, m20) = (mid(0, 1), mid(1, 2), mid(2, 0));
            let p = [(x[0], y[0]), (x[1], y[1]), (x[2], y[2])];
            for tri in [
                [p[0], m01, m20],
                [m01, p[1], m12],
                [m20, m12, p[2]],
                [m01, m12, m20],
            ] {
                stack.push((tri.map(|q| q.0), tri.map(|q| q.1), depth + 1));
            }
        }
        None
    }
}
