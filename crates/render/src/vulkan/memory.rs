//! Buffers: each in its own allocation of host-visible, coherent memory
//! (the host writes inputs and reads results directly; a CPU device has
//! nothing else), with a device address where the device enabled them.
//! Freed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// A buffer and its memory.
pub(crate) struct Buffer {
    core: Rc<Core>,
    pub(crate) handle: vk::Buffer,
    memory: vk::DeviceMemory,
    /// Its size (a multiple of 4, at least 4).
    pub(crate) bytes: u64,
    /// Its device address (0 where the device has none).
    pub(crate) address: vk::DeviceAddress,
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: every submission that used the buffer was waited for;
        // null handles (a buffer that failed part-way) are ignored.
        unsafe {
            self.core.raw.destroy_buffer(self.handle, None);
            self.core.raw.free_memory(self.memory, None);
        }
    }
}

/// The first memory type among `accepted` (a resource's
/// `memory_type_bits`) whose properties include `flags`.
pub(super) fn memory_type(
    memory: &vk::PhysicalDeviceMemoryProperties,
    accepted: u32,
    flags: vk::MemoryPropertyFlags,
) -> Option<u32> {
    let types = &memory.memory_types[..memory.memory_type_count as usize];
    (0..types.len())
        .find(|&i| accepted & (1 << i) != 0 && types[i].property_flags.contains(flags))
        .map(|i| i as u32)
}

impl Device {
    /// A zeroed buffer of at least `bytes` bytes (4 when 0: empty buffers
    /// are invalid) for `usage`.
    pub(crate) fn buffer(
        &self,
        bytes: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer, RenderError> {
        let core = &self.core;
        let d = &core.raw;
        let bytes = bytes.max(4).next_multiple_of(4);
        let usage = if core.buffer_addresses {
            usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
        } else {
            usage
        };
        let info = vk::BufferCreateInfo::default()
            .size(bytes)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: a valid device and create info.
        let handle = unsafe { d.create_buffer(&info, None) }.map_err(failed("vkCreateBuffer"))?;
        let mut buffer = Buffer {
            core: Rc::clone(core),
            handle,
            memory: vk::DeviceMemory::null(),
            bytes,
            address: 0,
        };
        // SAFETY: the buffer was just created on this device.
        let needs = unsafe { d.get_buffer_memory_requirements(handle) };
        let wanted = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let index = memory_type(&core.memory, needs.memory_type_bits, wanted)
            .ok_or(RenderError::NoHostVisibleMemory)?;
        let mut flags =
            vk::MemoryAllocateFlagsInfo::default().flags(vk::MemoryAllocateFlags::DEVICE_ADDRESS);
        let mut alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(needs.size)
            .memory_type_index(index);
        if core.buffer_addresses {
            alloc = alloc.push_next(&mut flags);
        }
        // SAFETY: a valid allocate info (on failure `buffer`'s drop
        // destroys the buffer).
        buffer.memory = unsafe { d.allocate_memory(&alloc, None) }.map_err(|result| {
            RenderError::Allocation {
                bytes: needs.size,
                result,
            }
        })?;
        // SAFETY: memory of a type the buffer accepts, large enough, unbound.
        unsafe { d.bind_buffer_memory(handle, buffer.memory, 0) }
            .map_err(failed("vkBindBufferMemory"))?;
        if core.buffer_addresses {
            let info = vk::BufferDeviceAddressInfo::default().buffer(handle);
            // SAFETY: a buffer created with SHADER_DEVICE_ADDRESS, bound.
            buffer.address = unsafe { d.get_buffer_device_address(&info) };
        }
        buffer.write(0, &[])?;
        Ok(buffer)
    }
}

impl Buffer {
    /// Zeroes the buffer and copies `bytes` to its offset `at`.
    ///
    /// # Panics
    /// If `bytes` would reach past the buffer (the callers size buffers
    /// for what they write).
    pub(crate) fn write(&self, at: u64, bytes: &[u8]) -> Result<(), RenderError> {
        assert!(at + bytes.len() as u64 <= self.bytes, "write past a buffer");
        let d = &self.core.raw;
        // SAFETY: host-visible memory bound to this buffer, mapped whole,
        // of `self.bytes` bytes (checked above), unmapped before return;
        // no submission is pending (each is waited for).
        unsafe {
            let base = d
                .map_memory(self.memory, 0, self.bytes, vk::MemoryMapFlags::empty())
                .map_err(failed("vkMapMemory"))?
                .cast::<u8>();
            std::ptr::write_bytes(base, 0, self.bytes as usize);
            std::ptr::copy_nonoverlapping(bytes.as_ptr(), base.add(at as usize), bytes.len());
            d.unmap_memory(self.memory);
        }
        Ok(())
    }

    /// The first `words` words of the buffer.
    ///
    /// # Panics
    /// If the buffer has fewer words.
    pub(crate) fn read(&self, words: usize) -> Result<Vec<u32>, RenderError> {
        assert!(4 * words as u64 <= self.bytes, "read past a buffer");
        let d = &self.core.raw;
        let mut out = vec![0u32; words];
        // SAFETY: as in `write`; `words` fit in the buffer (checked above).
        unsafe {
            let at = d
                .map_memory(self.memory, 0, self.bytes, vk::MemoryMapFlags::empty())
                .map_err(failed("vkMapMemory"))?;
            std::ptr::copy_nonoverlapping(at.cast::<u32>(), out.as_mut_ptr(), words);
            d.unmap_memory(self.memory);
        }
        Ok(out)
    }
}
