//! Samplers of the sampler lookup: one per (filter, address modes, border
//! colour) the scene's meshes use, as renderers create them (level 0 only:
//! mipmap mode nearest, `maxLod = 0`; normalized coordinates; no
//! anisotropy, no comparison). Destroyed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// What a sampler is made of: the filter (magnification and
/// minification alike), the address modes of `u` and `v`, and the border
/// colour (used by `CLAMP_TO_BORDER` only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct SamplerKey {
    pub(crate) filter: vk::Filter,
    pub(crate) address_u: vk::SamplerAddressMode,
    pub(crate) address_v: vk::SamplerAddressMode,
    pub(crate) border: vk::BorderColor,
}

/// A sampler.
pub(crate) struct Sampler {
    core: Rc<Core>,
    pub(crate) handle: vk::Sampler,
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: every submission whose descriptor set named the sampler
        // was waited for.
        unsafe { self.core.raw.destroy_sampler(self.handle, None) };
    }
}

impl Device {
    /// A sampler of `key`. `MIRROR_CLAMP_TO_EDGE` needs the device's
    /// `samplerMirrorClampToEdge`, enabled with the sampler lookup (the
    /// renderer checks it first).
    pub(crate) fn sampler(&self, key: SamplerKey) -> Result<Sampler, RenderError> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(key.filter)
            .min_filter(key.filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(key.address_u)
            .address_mode_v(key.address_v)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .mip_lod_bias(0.0)
            .anisotropy_enable(false)
            .max_anisotropy(1.0)
            .compare_enable(false)
            .min_lod(0.0)
            .max_lod(0.0)
            .border_color(key.border)
            .unnormalized_coordinates(false);
        // SAFETY: a valid create info on a live device.
        let handle = unsafe { self.core.raw.create_sampler(&info, None) }
            .map_err(failed("vkCreateSampler"))?;
        Ok(Sampler {
            core: Rc::clone(&self.core),
            handle,
        })
    }
}
