//! The [`Renderer`]: a scene and its micromaps on a Vulkan device (the
//! inputs in storage buffers; one BLAS per mesh and a TLAS with one
//! instance per placement; where asked, the driver's micromap attached to
//! a second set of BLASes under two more TLASes, 4-state and forced
//! 2-state; the tracers' pipelines, per lookup; for the sampler lookup, an
//! image per texture and a sampler per sampler state), and one traced
//! [`Frame`] per [`Renderer::render`].

use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::{
    counters_from_words, records_from_words, Frame, COUNTER_WORDS, MAX_PIXELS, PIXEL_WORDS,
    RECORD_WORDS,
};
use crate::method::{Faults, Lookup, Method, Tracer};
use crate::scene::{Micromaps, Scene, SceneMesh, SceneTexture};
use crate::spirv;
use crate::trees::tree_buffers;
use crate::vulkan::{
    AccelerationStructure, Bindings, BlasInstance, Buffer, Device, DeviceInfo, DeviceRequest,
    DeviceSelector, Features, Image, Launch, Micromap, MicromapAttachment, Pipeline,
    RayTracingStages, Sampler, SamplerKey, Timing,
};
use ash::vk;
use micromap_index::bake::{AddressMode, Filter};
use std::collections::BTreeMap;

/// Storage buffers of the tracers, bindings `1..=STORAGE_BINDINGS` (the
/// acceleration structure is binding 0): the scene and micromaps (1..=9),
/// the pixels and the counters.
const STORAGE_BINDINGS: u32 = 11;
/// Push-constant bytes (8 words, 4 `vec4`).
const PUSH_BYTES: u32 = 96;
/// The tracers' descriptor set and push constants (the shader lookup's;
/// the sampler lookup's adds a combined image sampler per mesh).
const BINDINGS: Bindings = Bindings {
    acceleration_structure: true,
    storage: STORAGE_BINDINGS,
    textures: 0,
    push_bytes: PUSH_BYTES,
};

/// How a [`Renderer`] is set up.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RendererOptions {
    /// The device to open (default: the first with what the rest needs).
    pub device: Option<DeviceSelector>,
    /// The tracers to build; the device must have each one's extension
    /// (`VK_KHR_ray_query`, `VK_KHR_ray_tracing_pipeline`). Empty: both.
    pub tracers: Vec<Tracer>,
    /// Whether to build the driver's micromaps for [`Method::Hardware`]
    /// and [`Method::Hardware2`] (the device must have
    /// `VK_EXT_opacity_micromap`).
    pub hardware: bool,
    /// The lookups to build (what reads the texture for the alpha test).
    /// Empty: the shader's.
    pub lookups: Vec<Lookup>,
}

impl Default for RendererOptions {
    fn default() -> RendererOptions {
        RendererOptions {
            device: None,
            tracers: Tracer::ALL.to_vec(),
            hardware: false,
            lookups: vec![Lookup::Shader],
        }
    }
}

/// The scene's acceleration structures: a BLAS per drawn mesh and the
/// TLASes over them.
struct Placed {
    // Instanced by the TLASes: kept while they are.
    _blases: Vec<AccelerationStructure>,
    tlases: Vec<AccelerationStructure>,
}

/// The driver's micromap and the structures that use it.
struct HardwareScene {
    /// TLAS 0: as baked; TLAS 1: forced to 2 states.
    placed: Placed,
    // Referred to by the BLASes.
    _micromap: Micromap,
    _indices: Buffer,
}

/// The sampler lookup's textures: an image per texture, a sampler per
/// sampler state, and per mesh the pair its descriptor names.
struct SamplerTextures {
    // Named by `per_mesh`: kept while it is.
    _images: Vec<Image>,
    _samplers: Vec<Sampler>,
    per_mesh: Vec<(vk::ImageView, vk::Sampler)>,
}

/// The sampler state of a mesh, or why the sampler lookup cannot read it.
fn sampler_key(device: &Device, mesh: usize, m: &SceneMesh) -> Result<SamplerKey, RenderError> {
    let s = m.material.sampler;
    let mode = |a: AddressMode| match a {
        AddressMode::Repeat => Ok(vk::SamplerAddressMode::REPEAT),
        AddressMode::MirroredRepeat => Ok(vk::SamplerAddressMode::MIRRORED_REPEAT),
        AddressMode::ClampToEdge => Ok(vk::SamplerAddressMode::CLAMP_TO_EDGE),
        AddressMode::ClampToBorder => Ok(vk::SamplerAddressMode::CLAMP_TO_BORDER),
        AddressMode::MirrorClampToEdge if device.info().mirror_clamp_to_edge => {
            Ok(vk::SamplerAddressMode::MIRROR_CLAMP_TO_EDGE)
        }
        AddressMode::MirrorClampToEdge => Err(RenderError::SamplerMirrorClamp {
            device: device.info().label(),
            mesh,
        }),
    };
    let (address_u, address_v) = (mode(s.address_u)?, mode(s.address_v)?);
    let clamps_to_border =
        [address_u, address_v].contains(&vk::SamplerAddressMode::CLAMP_TO_BORDER);
    // The border colour is read by CLAMP_TO_BORDER only.
    let border = if !clamps_to_border || s.border_alpha.to_bits() == 0.0f32.to_bits() {
        vk::BorderColor::FLOAT_TRANSPARENT_BLACK
    } else if s.border_alpha.to_bits() == 1.0f32.to_bits() {
        vk::BorderColor::FLOAT_OPAQUE_WHITE
    } else {
        return Err(RenderError::SamplerBorder {
            mesh,
            alpha: s.border_alpha,
        });
    };
    Ok(SamplerKey {
        filter: match s.filter {
            Filter::Nearest => vk::Filter::NEAREST,
            Filter::Linear => vk::Filter::LINEAR,
        },
        address_u,
        address_v,
        border,
    })
}

/// The texels of `texture` (number `index`) as `R8_UNORM` bytes, each alpha
/// `c / 255` (within binary32 rounding).
fn alpha_bytes(index: usize, texture: &SceneTexture) -> Result<Vec<u8>, RenderError> {
    let width = texture.width.max(1);
    texture
        .alphas
        .iter()
        .enumerate()
        .map(|(i, &a)| {
            let c = (f64::from(a) * 255.0).round();
            if (0.0..=255.0).contains(&c) && (f64::from(a) * 255.0 - c).abs() < 1e-3 {
                Ok(c as u8)
            } else {
                Err(RenderError::SamplerTexture {
                    texture: index,
                    texel: (i as u32 % width, i as u32 / width),
                    alpha: a,
                })
            }
        })
        .collect()
}

/// The sampler lookup's images and samplers for `scene`, after checking
/// that the device and every mesh's sampler state allow it.
fn sampler_textures(device: &Device, scene: &Scene) -> Result<SamplerTextures, RenderError> {
    if !device.sampler_lookup_enabled() {
        return Err(RenderError::SamplerIndexing {
            device: device.info().label(),
        });
    }
    let keys = scene
        .meshes()
        .iter()
        .enumerate()
        .map(|(i, m)| sampler_key(device, i, m))
        .collect::<Result<Vec<_>, _>>()?;
    let mut images = Vec::new();
    for (i, t) in scene.textures().iter().enumerate() {
        images.push(device.alpha_image(t.width, t.height, &alpha_bytes(i, t)?)?);
    }
    let mut samplers = Vec::new();
    let mut by_key = BTreeMap::new();
    for &key in &keys {
        if let std::collections::btree_map::Entry::Vacant(e) = by_key.entry(key) {
            samplers.push(device.sampler(key)?);
            e.insert(samplers[samplers.len() - 1].handle);
        }
    }
    let per_mesh = scene
        .meshes()
        .iter()
        .zip(&keys)
        .map(|(m, key)| (images[m.texture].view, by_key[key]))
        .collect();
    Ok(SamplerTextures {
        _images: images,
        _samplers: samplers,
        per_mesh,
    })
}

/// A scene on the device, ready to trace.
pub struct Renderer {
    device: Device,
    /// The ray query tracer's compute pipeline, per lookup
    /// ([`Lookup::ALL`]'s order).
    query: [Option<Pipeline>; 2],
    /// The ray tracing pipeline, per lookup.
    ray_tracing: [Option<Pipeline>; 2],
    /// The sampler lookup's images and samplers, where it was built.
    textures: Option<SamplerTextures>,
    emulated: Placed,
    hardware: Option<HardwareScene>,
    /// Bindings 1..=9 (scene and micromaps).
    inputs: Vec<Buffer>,
    has_micromaps: bool,
    index_width: u32,
}

fn words_to_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// `(count, level, format)` entries of a histogram of (level, states).
fn usage(counts: &std::collections::BTreeMap<(u32, u32), u64>) -> Vec<vk::MicromapUsageEXT> {
    counts
        .iter()
        .map(|(&(level, states), &count)| vk::MicromapUsageEXT {
            count: count as u32,
            subdivision_level: level,
            format: if states == 2 { 1 } else { 2 },
        })
        .collect()
}

/// One BLAS per mesh with triangles and instances (with `micromap`, its
/// index buffer at `indices` of `width` bytes per index, attached), and a
/// TLAS per entry of `flags` with every instance of every mesh.
fn place(
    device: &Device,
    scene: &Scene,
    micromap: Option<(&Micromap, &Micromaps, vk::DeviceAddress)>,
    flags: &[vk::GeometryInstanceFlagsKHR],
) -> Result<Placed, RenderError> {
    let mut blases = Vec::new();
    let mut meshes = Vec::new();
    for m in 0..scene.mesh_count() {
        let range = scene.mesh_triangles(m);
        if range.is_empty() || scene.instances(m).is_empty() {
            continue;
        }
        let vertices: Vec<[f32; 3]> = scene.positions()[range.clone()]
            .iter()
            .flatten()
            .copied()
            .collect();
        let blas = match micromap {
            None => device.triangle_blas(&vertices, None)?,
            Some((micromap, maps, indices)) => {
                let width = u64::from(maps.index_width_bytes());
                let usage = usage(&maps.level_counts(range.clone()).levels);
                let attachment = MicromapAttachment {
                    micromap,
                    index_address: indices + width * range.start as u64,
                    index_type: if width == 2 {
                        vk::IndexType::UINT16
                    } else {
                        vk::IndexType::UINT32
                    },
                    index_stride: width,
                    usage: &usage,
                };
                device.triangle_blas(&vertices, Some(&attachment))?
            }
        };
        blases.push(blas);
        meshes.push((m, range.start as u32));
    }
    let mut tlases = Vec::new();
    for &f in flags {
        let instances: Vec<BlasInstance<'_>> = meshes
            .iter()
            .zip(&blases)
            .flat_map(|(&(m, first), blas)| {
                scene
                    .instances(m)
                    .iter()
                    .map(move |&transform| BlasInstance {
                        blas,
                        transform,
                        custom_index: first,
                        flags: f,
                    })
            })
            .collect();
        tlases.push(device.tlas(&instances)?);
    }
    Ok(Placed {
        _blases: blases,
        tlases,
    })
}

/// The driver's micromap of `maps` and the scene's structures with it
/// attached, after checking that the device takes its levels and width.
fn hardware_scene(
    device: &Device,
    scene: &Scene,
    maps: &Micromaps,
) -> Result<HardwareScene, RenderError> {
    if maps.index_width_bytes() == 1 {
        return Err(RenderError::MicromapIndexWidth);
    }
    let [max2, max4] = device.info().max_micromap_levels.unwrap_or([0, 0]);
    for (record, map) in maps.read().micromaps.iter().enumerate() {
        let states = map.format().states();
        let max = if states == 2 { max2 } else { max4 };
        if map.level().get() > max {
            return Err(RenderError::MicromapLevel {
                record,
                level: map.level().get(),
                states,
                max,
            });
        }
    }
    let micromap = device.micromap(maps.data(), maps.records(), &usage(&maps.record_counts()))?;
    let indices = device.buffer(
        maps.indices().len() as u64,
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR,
    )?;
    indices.write(0, maps.indices())?;
    let cull = vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE;
    let placed = place(
        device,
        scene,
        Some((&micromap, maps, indices.address)),
        &[
            cull,
            cull | vk::GeometryInstanceFlagsKHR::FORCE_OPACITY_MICROMAP_2_STATE_EXT,
        ],
    )?;
    Ok(HardwareScene {
        placed,
        _micromap: micromap,
        _indices: indices,
    })
}

impl Renderer {
    /// Opens a Vulkan device with what `options` asks for, builds its
    /// tracers and puts `scene` and `micromaps` (one index per scene
    /// triangle; `None`: only [`Method::AlphaTest`] can be traced) on it.
    pub fn new(
        scene: &Scene,
        micromaps: Option<&Micromaps>,
        options: &RendererOptions,
    ) -> Result<Renderer, RenderError> {
        if let Some(m) = micromaps {
            m.check_for(scene)?;
        }
        let tracers = if options.tracers.is_empty() {
            Tracer::ALL.to_vec()
        } else {
            options.tracers.clone()
        };
        let lookups = if options.lookups.is_empty() {
            vec![Lookup::Shader]
        } else {
            options.lookups.clone()
        };
        let device = Device::open(&DeviceRequest {
            select: options.device.clone(),
            required: Features {
                acceleration_structure: true,
                ray_query: tracers.contains(&Tracer::Query),
                ray_tracing_pipeline: tracers.contains(&Tracer::Pipeline),
                opacity_micromap: options.hardware,
            },
            optional: Features::default(),
            sampler_lookup: lookups.contains(&Lookup::Sampler),
        })?;
        // Checked (and uploaded) before any pipeline is built.
        let textures = if lookups.contains(&Lookup::Sampler) {
            Some(sampler_textures(&device, scene)?)
        } else {
            None
        };
        let mut query = [None, None];
        let mut ray_tracing = [None, None];
        for (l, lookup) in Lookup::ALL.into_iter().enumerate() {
            if !lookups.contains(&lookup) {
                continue;
            }
            let bindings = match &textures {
                Some(t) if lookup == Lookup::Sampler => Bindings {
                    textures: t.per_mesh.len() as u32,
                    ..BINDINGS
                },
                _ => BINDINGS,
            };
            if tracers.contains(&Tracer::Query) {
                let spirv = match lookup {
                    Lookup::Shader => spirv::query(),
                    Lookup::Sampler => spirv::query_sampler(),
                };
                query[l] = Some(device.compute_pipeline(&spirv, bindings)?);
            }
            if tracers.contains(&Tracer::Pipeline) {
                let [raygen, miss, closest_hit, mut any_hit] = spirv::pipeline();
                if lookup == Lookup::Sampler {
                    any_hit = spirv::any_hit_sampler();
                }
                let stages = RayTracingStages {
                    raygen: &raygen,
                    miss: &miss,
                    closest_hit: &closest_hit,
                    any_hit: &any_hit,
                };
                ray_tracing[l] = Some(device.ray_tracing_pipeline(&stages, bindings)?);
            }
        }
        let emulated = place(
            &device,
            scene,
            None,
            &[vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE],
        )?;
        let hardware = match (options.hardware, micromaps) {
            (false, _) => None,
            (true, None) => return Err(RenderError::NeedsMicromaps(Method::Hardware)),
            (true, Some(maps)) => Some(hardware_scene(&device, scene, maps)?),
        };
        let (trees, dir) = match micromaps {
            Some(m) => tree_buffers(m)?,
            None => (Vec::new(), Vec::new()),
        };
        let empty: &[u8] = &[];
        let (data, records, indices) = micromaps.map_or((empty, empty, empty), |m| {
            (m.data(), m.records(), m.indices())
        });
        let contents: [Vec<u8>; 9] = [
            scene.triangle_bytes(),
            scene.mesh_of_bytes(),
            scene.mesh_info_bytes(),
            scene.texel_bytes(),
            data.to_vec(),
            records.to_vec(),
            indices.to_vec(),
            words_to_bytes(&trees),
            words_to_bytes(&dir),
        ];
        let mut inputs = Vec::new();
        for bytes in &contents {
            let b = device.buffer(bytes.len() as u64, vk::BufferUsageFlags::STORAGE_BUFFER)?;
            b.write(0, bytes)?;
            inputs.push(b);
        }
        let renderer = Renderer {
            device,
            query,
            ray_tracing,
            textures,
            emulated,
            hardware,
            inputs,
            has_micromaps: micromaps.is_some(),
            index_width: micromaps.map_or(4, Micromaps::index_width_bytes),
        };
        // lavapipe compiles a pipeline at its first dispatch: one pixel
        // here keeps that out of every frame's time.
        for tracer in renderer.tracers() {
            for lookup in renderer.lookups() {
                renderer.render(
                    (tracer, lookup),
                    Method::AlphaTest,
                    &Camera::framing(scene.bounds().unwrap_or_default(), 1.0),
                    (1, 1),
                    Faults::default(),
                    0,
                )?;
            }
        }
        Ok(renderer)
    }

    /// The device, driver and Vulkan version, e.g. `llvmpipe (LLVM 15.0.6,
    /// 256 bits) (Vulkan 1.4.305, llvmpipe Mesa 25.0.7-2~bpo12+1 ...)`.
    #[must_use]
    pub fn device_name(&self) -> String {
        self.device.info().label()
    }

    /// What the device is and has.
    #[must_use]
    pub fn device_info(&self) -> &DeviceInfo {
        self.device.info()
    }

    /// The features enabled on the device: each tracer's extension and,
    /// for the hardware methods, `VK_EXT_opacity_micromap`; nothing else.
    #[must_use]
    pub fn enabled(&self) -> Features {
        self.device.enabled()
    }

    /// The tracers built ([`RendererOptions::tracers`]), the ray query
    /// first.
    #[must_use]
    pub fn tracers(&self) -> Vec<Tracer> {
        let mut t = Vec::new();
        if self.query.iter().any(Option::is_some) {
            t.push(Tracer::Query);
        }
        if self.ray_tracing.iter().any(Option::is_some) {
            t.push(Tracer::Pipeline);
        }
        t
    }

    /// The lookups built ([`RendererOptions::lookups`]), the shader's
    /// first.
    #[must_use]
    pub fn lookups(&self) -> Vec<Lookup> {
        Lookup::ALL
            .into_iter()
            .enumerate()
            .filter(|&(l, _)| self.query[l].is_some() || self.ray_tracing[l].is_some())
            .map(|(_, lookup)| lookup)
            .collect()
    }

    /// One launch of `pipeline` over `tlas`: the pixel words
    /// ([`PIXEL_WORDS`] per pixel), the counter words and the timing.
    #[allow(clippy::too_many_arguments)]
    fn trace(
        &self,
        (tracer, lookup, pipeline, tlas): (Tracer, Lookup, &Pipeline, &AccelerationStructure),
        method: Method,
        basis: &[[f32; 4]; 4],
        (width, height): (u32, u32),
        faults: Faults,
        record_limit: u32,
        max_records: u32,
    ) -> Result<(Vec<u32>, Vec<u32>, Timing), RenderError> {
        let d = &self.device;
        let pixels = u64::from(width) * u64::from(height);
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let hits = d.buffer(4 * PIXEL_WORDS as u64 * pixels, usage)?;
        let counter_words = COUNTER_WORDS + RECORD_WORDS * max_records as usize;
        let counters = d.buffer(4 * counter_words as u64, usage)?;
        let i = &self.inputs;
        let storage: [&Buffer; STORAGE_BINDINGS as usize] = [
            &i[0], &i[1], &i[2], &i[3], &i[4], &i[5], &i[6], &i[7], &i[8], &hits, &counters,
        ];
        let fault = u32::from(faults.swap_barycentrics) | (u32::from(faults.flip_known) << 1);
        let mut push: Vec<u8> = [
            width,
            height,
            method.code(),
            self.index_width,
            max_records,
            fault,
            record_limit,
            0,
        ]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
        push.extend(basis.iter().flatten().flat_map(|x| x.to_le_bytes()));
        let launch = match tracer {
            Tracer::Query => Launch::Groups([width.div_ceil(8), height.div_ceil(8), 1]),
            Tracer::Pipeline => Launch::Rays(width, height),
        };
        let textures: &[(vk::ImageView, vk::Sampler)] = match (lookup, &self.textures) {
            (Lookup::Sampler, Some(t)) => &t.per_mesh,
            _ => &[],
        };
        let timing = d.run(pipeline, Some(tlas), (&storage, textures), &push, launch)?;
        Ok((
            hits.read(PIXEL_WORDS * pixels as usize)?,
            counters.read(counter_words)?,
            timing,
        ))
    }

    /// Traces one `width x height` frame with `tracer`, `lookup` and
    /// `method`, keeping the first `max_records` contradictions in pixel order (where
    /// more were recorded, a second launch records those of the first
    /// pixels only, so both tracers list the same ones);
    /// [`RenderError::NoTracer`] for a tracer not in [`Renderer::tracers`],
    /// [`RenderError::NoLookup`] for a lookup not in [`Renderer::lookups`],
    /// [`RenderError::NoHardwareMicromaps`] for a hardware method without
    /// [`RendererOptions::hardware`].
    pub fn render(
        &self,
        (tracer, lookup): (Tracer, Lookup),
        method: Method,
        camera: &Camera,
        (width, height): (u32, u32),
        faults: Faults,
        max_records: u32,
    ) -> Result<Frame, RenderError> {
        if method != Method::AlphaTest && !self.has_micromaps {
            return Err(RenderError::NeedsMicromaps(method));
        }
        let l = usize::from(lookup == Lookup::Sampler);
        let chosen = match tracer {
            Tracer::Query => &self.query,
            Tracer::Pipeline => &self.ray_tracing,
        };
        if chosen.iter().all(Option::is_none) {
            return Err(RenderError::NoTracer {
                device: self.device_name(),
                tracer,
            });
        }
        let Some(pipeline) = chosen[l].as_ref() else {
            return Err(RenderError::NoLookup(lookup));
        };
        let tlas = match method {
            Method::Hardware | Method::Hardware2 => {
                let Some(hw) = &self.hardware else {
                    return Err(RenderError::NoHardwareMicromaps {
                        device: self.device_name(),
                    });
                };
                &hw.placed.tlases[usize::from(method == Method::Hardware2)]
            }
            _ => &self.emulated.tlases[0],
        };
        let pixels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || pixels > MAX_PIXELS {
            return Err(RenderError::Size { width, height });
        }
        let max_records = max_records.min(1 << 16);
        let basis = camera.basis(width, height)?;
        let what = (tracer, lookup, pipeline, tlas);
        let (words, c, timing) = self.trace(
            what,
            method,
            &basis,
            (width, height),
            faults,
            u32::MAX,
            max_records,
        )?;
        let mut contradictions = records_from_words(&c, max_records, width);
        if c[7] > max_records && max_records > 0 {
            // The first pixels (row-major) that hold max_records
            // contradictions, all of theirs recorded in a second launch.
            let mut sum = 0u64;
            let mut limit = pixels as u32;
            for (p, w) in words.chunks_exact(PIXEL_WORDS).enumerate() {
                sum += u64::from(w[2]);
                if sum >= u64::from(max_records) {
                    limit = p as u32 + 1;
                    break;
                }
            }
            let needed = sum.min(1 << 20) as u32;
            let (_, c2, _) =
                self.trace(what, method, &basis, (width, height), faults, limit, needed)?;
            contradictions = records_from_words(&c2, needed, width);
            contradictions.truncate(max_records as usize);
        }
        Ok(Frame {
            tracer,
            lookup,
            method,
            width,
            height,
            hits: words
                .chunks_exact(PIXEL_WORDS)
                .map(|h| [h[0], h[1]])
                .collect(),
            counters: counters_from_words(&c),
            contradictions,
            cpu_seconds: timing.cpu,
            wall_seconds: timing.wall,
            device_seconds: timing.device,
        })
    }
}
