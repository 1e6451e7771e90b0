//! Opacity micromaps built by the driver (`VK_EXT_opacity_micromap`) from
//! a bake's buffers: the data and the triangle records (8-byte
//! `VkMicromapTriangleEXT`, the layout bake writes) copied to 256-byte
//! aligned addresses, the usage counts, a storage buffer of the size the
//! driver asks for. Destroyed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use super::memory::Buffer;
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// The alignment `vkCmdBuildMicromapsEXT` demands of the data and
/// triangle-array addresses (VUID-vkCmdBuildMicromapsEXT-pInfos-07515,
/// -07516), which also covers the scratch's.
const ALIGNMENT: u64 = 256;

/// A built micromap and its storage.
pub(crate) struct Micromap {
    core: Rc<Core>,
    pub(crate) handle: vk::MicromapEXT,
    // Destroyed after the micromap (fields drop after `drop`).
    _storage: Buffer,
}

impl Drop for Micromap {
    fn drop(&mut self) {
        if let Some(omm) = &self.core.micromap {
            // SAFETY: no pending command uses it (every submission is waited
            // for; the structures that refer to it hold it); a null handle
            // is ignored.
            unsafe { (omm.fp().destroy_micromap_ext)(omm.device(), self.handle, std::ptr::null()) };
        }
    }
}

impl Device {
    /// A buffer of `bytes` at a [`ALIGNMENT`]-aligned address, for `usage`;
    /// the buffer and the address.
    fn aligned_input(
        &self,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<(Buffer, vk::DeviceAddress), RenderError> {
        let buffer = self.buffer(bytes.len() as u64 + ALIGNMENT, usage)?;
        let start = buffer.address.next_multiple_of(ALIGNMENT);
        buffer.write(start - buffer.address, bytes)?;
        Ok((buffer, start))
    }

    /// The micromap of `records` (8 bytes each) over `data`, with `usage`
    /// its histogram of (count, level, format); built on the device and
    /// waited for.
    pub(crate) fn micromap(
        &self,
        data: &[u8],
        records: &[u8],
        usage: &[vk::MicromapUsageEXT],
    ) -> Result<Micromap, RenderError> {
        let Some(omm) = &self.core.micromap else {
            return Err(RenderError::Vulkan {
                call: "vkCreateMicromapEXT",
                result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
            });
        };
        let (fp, device) = (omm.fp(), omm.device());
        let input = vk::BufferUsageFlags::MICROMAP_BUILD_INPUT_READ_ONLY_EXT;
        let (_data, data_address) = self.aligned_input(data, input)?;
        let (_records, records_address) = self.aligned_input(records, input)?;
        let mut info = vk::MicromapBuildInfoEXT::default()
            .ty(vk::MicromapTypeEXT::OPACITY_MICROMAP)
            .flags(vk::BuildMicromapFlagsEXT::PREFER_FAST_TRACE)
            .mode(vk::BuildMicromapModeEXT::BUILD)
            .usage_counts(usage)
            .data(vk::DeviceOrHostAddressConstKHR {
                device_address: data_address,
            })
            .triangle_array(vk::DeviceOrHostAddressConstKHR {
                device_address: records_address,
            })
            .triangle_array_stride(8);
        let mut sizes = vk::MicromapBuildSizesInfoEXT::default();
        // SAFETY: a valid build info whose usage counts outlive the call.
        unsafe {
            (fp.get_micromap_build_sizes_ext)(
                device,
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &info,
                &mut sizes,
            );
        }
        let storage = self.buffer(
            sizes.micromap_size,
            vk::BufferUsageFlags::MICROMAP_STORAGE_EXT,
        )?;
        let create = vk::MicromapCreateInfoEXT::default()
            .buffer(storage.handle)
            .size(sizes.micromap_size)
            .ty(vk::MicromapTypeEXT::OPACITY_MICROMAP);
        let mut handle = vk::MicromapEXT::null();
        // SAFETY: a buffer of the size the driver asked for; `handle` is
        // written by the call.
        unsafe { (fp.create_micromap_ext)(device, &create, std::ptr::null(), &mut handle) }
            .result()
            .map_err(failed("vkCreateMicromapEXT"))?;
        let micromap = Micromap {
            core: Rc::clone(&self.core),
            handle,
            _storage: storage,
        };
        let scratch = self.buffer(
            sizes.build_scratch_size + ALIGNMENT,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        info = info
            .dst_micromap(handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch.address.next_multiple_of(ALIGNMENT),
            });
        // SAFETY: the micromap, scratch and inputs live until the wait in
        // `submit` returns; one build info.
        self.submit(|cmd| unsafe { (fp.cmd_build_micromaps_ext)(cmd, 1, &info) })?;
        Ok(micromap)
    }
}
