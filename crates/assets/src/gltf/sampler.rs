//! Samplers: glTF's codes (`samplers[i]`) and the library's
//! [`Sampler`] they become.

use super::reader::Reader;
use crate::AssetError;
use micromap_index::bake::{AddressMode, Filter, Sampler};

/// glTF's `REPEAT` wrap mode (the default of `wrapS` and `wrapT`).
pub(crate) const REPEAT: u32 = 10497;
/// glTF's `CLAMP_TO_EDGE` wrap mode.
pub(crate) const CLAMP_TO_EDGE: u32 = 33071;
/// glTF's `MIRRORED_REPEAT` wrap mode.
pub(crate) const MIRRORED_REPEAT: u32 = 33648;
/// glTF's `NEAREST` filter.
pub(crate) const NEAREST: u32 = 9728;
/// glTF's `LINEAR` filter.
pub(crate) const LINEAR: u32 = 9729;

/// A glTF sampler with its raw codes (`samplers[i]`, or the defaults when a
/// texture has none).
///
/// Wrap modes: [`REPEAT`] (10497), [`CLAMP_TO_EDGE`] (33071),
/// [`MIRRORED_REPEAT`] (33648). Filters: [`NEAREST`] (9728), [`LINEAR`]
/// (9729), and for `min_filter` also the mipmap modes 9984..=9987. The
/// reader checks that each code is one of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct GltfSampler {
    /// `wrapS`, the wrap mode along `u`; default [`REPEAT`].
    pub(crate) wrap_s: u32,
    /// `wrapT`, the wrap mode along `v`; default [`REPEAT`].
    pub(crate) wrap_t: u32,
    /// `magFilter`, if given.
    pub(crate) mag_filter: Option<u32>,
    /// `minFilter`, if given.
    pub(crate) min_filter: Option<u32>,
}

impl Default for GltfSampler {
    /// glTF's defaults: wrap [`REPEAT`] both ways, filters unspecified.
    fn default() -> Self {
        GltfSampler {
            wrap_s: REPEAT,
            wrap_t: REPEAT,
            mag_filter: None,
            min_filter: None,
        }
    }
}

impl GltfSampler {
    /// The sampler the runtime uses: `magFilter` `NEAREST` is
    /// [`Filter::Nearest`], `LINEAR` or unspecified [`Filter::Linear`]; the
    /// wrap modes as the address modes of the same names; border alpha 0
    /// (glTF has no clamp-to-border).
    pub(crate) fn to_sampler(self) -> Sampler {
        let address = |code| match code {
            MIRRORED_REPEAT => AddressMode::MirroredRepeat,
            CLAMP_TO_EDGE => AddressMode::ClampToEdge,
            _ => AddressMode::Repeat,
        };
        Sampler {
            filter: match self.mag_filter {
                Some(NEAREST) => Filter::Nearest,
                _ => Filter::Linear,
            },
            address_u: address(self.wrap_s),
            address_v: address(self.wrap_t),
            border_alpha: 0.0,
        }
    }
}

impl Reader<'_, '_> {
    pub(super) fn sampler(&self, index: usize, what: &str) -> Result<GltfSampler, AssetError> {
        let sampler = self.root.element("samplers", index, what)?;
        let code =
            |key: &str, valid: &[u32], default: Option<u32>| -> Result<Option<u32>, AssetError> {
                match sampler.opt_u32(key)? {
                    None => Ok(default),
                    Some(code) if valid.contains(&code) => Ok(Some(code)),
                    Some(code) => Err(sampler.error(
                        key,
                        format!("{code} is not one of the glTF codes {valid:?}"),
                    )),
                }
            };
        let wraps = [REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT];
        Ok(GltfSampler {
            wrap_s: code("wrapS", &wraps, Some(REPEAT))?.unwrap_or(REPEAT),
            wrap_t: code("wrapT", &wraps, Some(REPEAT))?.unwrap_or(REPEAT),
            mag_filter: code("magFilter", &[NEAREST, LINEAR], None)?,
            min_filter: code(
                "minFilter",
                &[NEAREST, LINEAR, 9984, 9985, 9986, 9987],
                None,
            )?,
        })
    }
}
