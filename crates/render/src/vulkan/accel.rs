//! Acceleration structures: a bottom-level one of triangles (not opaque,
//! so every candidate the traversal does not decide itself reaches the
//! shader; no duplicate any-hit calls), with an opacity micromap attached
//! where asked, and a top-level one of instances of them. Each is built on the device and
//! waited for; its storage lives with it, its scratch and inputs only for
//! the build. Destroyed when dropped.

use super::conv::failed;
use super::device::{Core, Device};
use super::memory::Buffer;
use super::micromap::Micromap;
use crate::error::RenderError;
use ash::vk;
use std::rc::Rc;

/// Scratch addresses must be aligned: 256 covers every driver's
/// `minAccelerationStructureScratchOffsetAlignment` we know.
const SCRATCH_ALIGNMENT: u64 = 256;

/// A built acceleration structure and its storage.
pub(crate) struct AccelerationStructure {
    core: Rc<Core>,
    pub(crate) handle: vk::AccelerationStructureKHR,
    /// Its device address (instances refer to bottom-level ones by it).
    pub(crate) address: vk::DeviceAddress,
    // Destroyed after the structure (fields drop after `drop`).
    _storage: Buffer,
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        if let Some(accel) = &self.core.accel {
            // SAFETY: no pending command uses it (every submission is
            // waited for); a null handle is ignored.
            unsafe { accel.destroy_acceleration_structure(self.handle, None) };
        }
    }
}

/// One instance of a bottom-level structure in a top-level one.
pub(crate) struct BlasInstance<'a> {
    pub(crate) blas: &'a AccelerationStructure,
    /// Row-major 3x4 object-to-world transform.
    pub(crate) transform: [f32; 12],
    /// `gl_InstanceCustomIndexEXT` (24 bits).
    pub(crate) custom_index: u32,
    pub(crate) flags: vk::GeometryInstanceFlagsKHR,
}

/// A micromap for a bottom-level structure's triangles: triangle `i`
/// takes the index at `index_address + i * index_stride`.
pub(crate) struct MicromapAttachment<'a> {
    pub(crate) micromap: &'a Micromap,
    pub(crate) index_address: vk::DeviceAddress,
    /// `UINT16` or `UINT32`.
    pub(crate) index_type: vk::IndexType,
    pub(crate) index_stride: u64,
    /// How many of the triangles use each (level, format).
    pub(crate) usage: &'a [vk::MicromapUsageEXT],
}

impl Device {
    fn accel(&self) -> Result<&ash::khr::acceleration_structure::Device, RenderError> {
        self.core.accel.as_ref().ok_or(RenderError::Vulkan {
            call: "vkCreateAccelerationStructureKHR",
            result: vk::Result::ERROR_EXTENSION_NOT_PRESENT,
        })
    }

    /// A buffer holding `bytes` for a build's input.
    fn build_input(&self, bytes: &[u8]) -> Result<Buffer, RenderError> {
        let buffer = self.buffer(
            bytes.len() as u64,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR,
        )?;
        buffer.write(0, bytes)?;
        Ok(buffer)
    }

    /// One acceleration structure of `ty` built from `geometry` with
    /// `count` primitives.
    fn build(
        &self,
        ty: vk::AccelerationStructureTypeKHR,
        geometry: vk::AccelerationStructureGeometryKHR<'_>,
        count: u32,
    ) -> Result<AccelerationStructure, RenderError> {
        let accel = self.accel()?;
        let geometries = [geometry];
        let mut info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(ty)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        // SAFETY: a valid build info with one geometry and one count.
        unsafe {
            accel.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &info,
                &[count],
                &mut sizes,
            );
        }
        let storage = self.buffer(
            sizes.acceleration_structure_size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR,
        )?;
        let create = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(storage.handle)
            .size(sizes.acceleration_structure_size)
            .ty(ty);
        // SAFETY: a buffer of the size the driver asked for.
        let handle = unsafe { accel.create_acceleration_structure(&create, None) }
            .map_err(failed("vkCreateAccelerationStructureKHR"))?;
        let info_address =
            vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(handle);
        // SAFETY: a structure of this device.
        let address = unsafe { accel.get_acceleration_structure_device_address(&info_address) };
        let structure = AccelerationStructure {
            core: Rc::clone(&self.core),
            handle,
            address,
            _storage: storage,
        };
        let scratch = self.buffer(
            sizes.build_scratch_size + SCRATCH_ALIGNMENT,
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        info = info
            .dst_acceleration_structure(handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch.address.next_multiple_of(SCRATCH_ALIGNMENT),
            });
        let range = [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count)];
        // SAFETY: the structure, scratch and inputs live until the wait in
        // `submit` returns.
        self.submit(|cmd| unsafe {
            accel.cmd_build_acceleration_structures(cmd, &[info], &[&range]);
        })?;
        Ok(structure)
    }

    /// The bottom-level structure of `vertices` (three per triangle, not
    /// indexed), not opaque, with `micromap` attached where given.
    pub(crate) fn triangle_blas(
        &self,
        vertices: &[[f32; 3]],
        micromap: Option<&MicromapAttachment<'_>>,
    ) -> Result<AccelerationStructure, RenderError> {
        let bytes: Vec<u8> = vertices
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let vertex_buffer = self.build_input(&bytes)?;
        let mut attachment = micromap.map(|m| {
            vk::AccelerationStructureTrianglesOpacityMicromapEXT::default()
                .index_type(m.index_type)
                .index_buffer(vk::DeviceOrHostAddressConstKHR {
                    device_address: m.index_address,
                })
                .index_stride(m.index_stride)
                .usage_counts(m.usage)
                .micromap(m.micromap.handle)
        });
        let mut triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
            .vertex_format(vk::Format::R32G32B32_SFLOAT)
            .vertex_data(vk::DeviceOrHostAddressConstKHR {
                device_address: vertex_buffer.address,
            })
            .vertex_stride(12)
            .max_vertex(vertices.len().saturating_sub(1) as u32)
            .index_type(vk::IndexType::NONE_KHR);
        if let Some(attachment) = &mut attachment {
            triangles = triangles.push_next(attachment);
        }
        // Not OPAQUE: every candidate reaches the shader.
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
            .flags(vk::GeometryFlagsKHR::NO_DUPLICATE_ANY_HIT_INVOCATION);
        self.build(
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            geometry,
            (vertices.len() / 3) as u32,
        )
    }

    /// The top-level structure of `instances`.
    pub(crate) fn tlas(
        &self,
        instances: &[BlasInstance<'_>],
    ) -> Result<AccelerationStructure, RenderError> {
        let records: Vec<vk::AccelerationStructureInstanceKHR> = instances
            .iter()
            .map(|i| vk::AccelerationStructureInstanceKHR {
                transform: vk::TransformMatrixKHR {
                    matrix: i.transform,
                },
                instance_custom_index_and_mask: vk::Packed24_8::new(i.custom_index, 0xff),
                instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
                    0,
                    i.flags.as_raw() as u8,
                ),
                acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
                    device_handle: i.blas.address,
                },
            })
            .collect();
        // SAFETY: plain-old-data structs of the API, viewed as bytes.
        let bytes = unsafe {
            std::slice::from_raw_parts(
                records.as_ptr().cast::<u8>(),
                std::mem::size_of_val(records.as_slice()),
            )
        };
        let instance_buffer = self.build_input(bytes)?;
        let data = vk::AccelerationStructureGeometryInstancesDataKHR::default().data(
            vk::DeviceOrHostAddressConstKHR {
                device_address: instance_buffer.address,
            },
        );
        let geometry = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR { instances: data });
        self.build(
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            geometry,
            instances.len() as u32,
        )
    }
}
