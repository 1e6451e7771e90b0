//! Which texel classes (opaque, transparent) a closed micro-triangle can
//! sample, in layers: the classes and blocks it reasons with
//! ([`classes`]), the texel tables with prefix sums ([`tables`]), the
//! image of a block of texel coordinates under the address modes
//! ([`wrap`]), the exact block search ([`search`]), and the per-leaf
//! classifier the walk calls ([`leaf`]), and linear filtering by value
//! ([`bilinear`]).

mod bilinear;
mod classes;
mod leaf;
mod search;
mod tables;
mod wrap;

pub(crate) use bilinear::PointReading;
pub(crate) use classes::{is_small, Block, Classes, Grid, Margin, Placed};
#[cfg(test)]
pub(crate) use classes::{NARROW_SHIFT, NARROW_WALK_COORDINATE};
pub(crate) use leaf::{Classifier, Points};
pub(crate) use tables::TexelClasses;
