//! A triangle's opacity: one micromap, or one state for the whole triangle
//! (a special index), borrowed ([`TriangleOpacity`], what the buffers'
//! builder takes) or owned ([`BakedOpacity`], what a bake makes and the
//! buffers resolve to).

use super::map::Micromap;
use super::state::State;
use crate::Level;

/// One triangle's opacity as given to [`MicromapBuffersBuilder::add_geometry`](super::MicromapBuffersBuilder::add_geometry).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TriangleOpacity<'a> {
    /// The triangle uses this micromap.
    Micromap(&'a Micromap),
    /// The whole triangle has this state (a special index, no data).
    Special(State),
}

/// What a triangle's micromap index will point at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BakedOpacity {
    /// A micromap of the requested level and format.
    Map(Micromap),
    /// One state for the whole triangle (a special index).
    Special(State),
}

impl BakedOpacity {
    /// The form [`MicromapBuffersBuilder`](crate::micromap::MicromapBuffersBuilder)
    /// takes.
    #[must_use]
    pub fn as_opacity(&self) -> TriangleOpacity<'_> {
        match self {
            BakedOpacity::Map(map) => TriangleOpacity::Micromap(map),
            BakedOpacity::Special(state) => TriangleOpacity::Special(*state),
        }
    }

    /// The state of micro-triangle `i`: the map's, or for a special index
    /// its one state whatever `i`; `None` past the end of the map.
    ///
    /// ```
    /// use micromap_index::micromap::BakedOpacity;
    /// use micromap_index::micromap::{Format, Micromap, State};
    /// use micromap_index::Level;
    /// let mut map = Micromap::new(Level::new(1).unwrap(), Format::FourState).unwrap();
    /// map.set(2, State::Opaque).unwrap();
    /// let baked = BakedOpacity::Map(map);
    /// assert_eq!(baked.state(2), Some(State::Opaque));
    /// assert_eq!(baked.state(4), None);
    /// assert_eq!(BakedOpacity::Special(State::UnknownOpaque).state(99), Some(State::UnknownOpaque));
    /// ```
    #[must_use]
    pub fn state(&self, i: u64) -> Option<State> {
        match self {
            BakedOpacity::Map(map) => map.get(i),
            BakedOpacity::Special(state) => Some(*state),
        }
    }

    /// The micromap's level; 0 for a special index (one state for the
    /// whole triangle, as a level-0 map would hold it).
    #[must_use]
    pub fn level(&self) -> Level {
        match self {
            BakedOpacity::Map(map) => map.level(),
            BakedOpacity::Special(_) => Level(0),
        }
    }
}
