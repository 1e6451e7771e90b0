//! What `render` writes about its frames: the pictures (a colour per mesh,
//! magenta differences), the contradictions as JSON and as lines, the
//! device as JSON, and the micromaps' levels per primitive. Pure functions
//! of the frames; `render_command` decides and writes.

use micromap_index_render::vulkan::{DeviceInfo, Features};
use micromap_index_render::{Classified, Frame, LevelCounts, Lookup, Method, Scene, Tracer};
use serde_json::{json, Value};

/// The name of `method`'s picture under `tracer` and `lookup` (`suffix`
/// "" or "-diff"): `METHOD.png`, `pipeline-METHOD.png`, and the sampler
/// lookup's with `sampler-` in front.
pub(super) fn picture_name(
    (lookup, tracer): (Lookup, Tracer),
    method: Method,
    suffix: &str,
) -> String {
    let lookup = match lookup {
        Lookup::Shader => "",
        Lookup::Sampler => "sampler-",
    };
    match tracer {
        Tracer::Query => format!("{lookup}{}{suffix}.png", method.name()),
        Tracer::Pipeline => format!("{lookup}pipeline-{}{suffix}.png", method.name()),
    }
}

/// A colour per mesh, a little brighter or darker per triangle.
pub(super) fn picture(frame: &Frame, scene: &Scene) -> Vec<u8> {
    const PALETTE: [[u8; 3]; 6] = [
        [96, 170, 72],
        [214, 160, 64],
        [80, 140, 210],
        [190, 96, 160],
        [220, 110, 80],
        [120, 190, 180],
    ];
    let mut mesh_index = std::collections::HashMap::new();
    frame
        .hits
        .iter()
        .flat_map(|&[hit, _]| {
            if hit == 0 {
                return [24, 24, 32];
            }
            let t = (hit - 1) as usize;
            let key = scene
                .mesh_of(t)
                .map(|m| (m.texture, m.material.cutoff.alpha().to_bits()));
            let next = mesh_index.len();
            let m = *mesh_index.entry(key).or_insert(next);
            let shade = 0.8 + 0.2 * ((t.wrapping_mul(2654435761) >> 8) % 256) as f32 / 255.0;
            PALETTE[m % PALETTE.len()].map(|c| (f32::from(c) * shade) as u8)
        })
        .collect()
}

/// The picture of `frame` against `reference` (whose picture is
/// `reference_rgb`): equal pixels dimmed, differing ones magenta; and how
/// many differ.
pub(super) fn difference(frame: &Frame, reference: &Frame, reference_rgb: &[u8]) -> (Vec<u8>, u64) {
    let mut differing = 0;
    let rgb = frame
        .hits
        .iter()
        .zip(&reference.hits)
        .enumerate()
        .flat_map(|(i, (a, b))| {
            if a == b {
                [0, 1, 2].map(|k| reference_rgb[3 * i + k] / 3)
            } else {
                differing += 1;
                [255, 0, 255]
            }
        })
        .collect();
    (rgb, differing)
}

fn hex(bits: u32) -> String {
    format!("0x{bits:08x}")
}

pub(super) fn contradiction_json(c: &Classified) -> Value {
    let r = &c.contradiction;
    json!({
        "pixel": [r.x, r.y],
        "triangle": r.triangle,
        "micro_triangle": c.micro_triangle,
        "shader_micro_triangle": r.micro_triangle,
        "level": c.level,
        "b1": hex(r.b1_bits),
        "b2": hex(r.b2_bits),
        "state": if r.state == 1 { "opaque" } else { "transparent" },
        "class": c.class.name(),
        "exact_texel_point": c.exact_texel_point,
        "exact_alpha_test": if c.exact_opaque { "opaque" } else { "transparent" },
        "exact_alpha": c.exact_alpha,
        "lookup_alpha": c.judged_alpha,
        "texels": c.texels.iter().map(|&(x, y, a)| json!({"x": x, "y": y, "alpha": a})).collect::<Vec<_>>(),
        "binary32_uv": c.binary32_uv,
    })
}

pub(super) fn contradiction_line(label: &str, c: &Classified) -> String {
    let r = &c.contradiction;
    let texels: Vec<String> = c
        .texels
        .iter()
        .map(|(x, y, a)| format!("({x}, {y}) alpha {a}"))
        .collect();
    format!(
        "{}: pixel ({}, {}) triangle {} micro-triangle {} (level {}) known {} at b1 = {}, b2 = {}: {}; the lookup compared alpha {}; exact point ({}, {}) texels reads {} -> alpha {} {}",
        label,
        r.x,
        r.y,
        r.triangle,
        c.micro_triangle,
        c.level.map_or("special".into(), |l| l.to_string()),
        if r.state == 1 { "opaque" } else { "transparent" },
        hex(r.b1_bits),
        hex(r.b2_bits),
        c.class.name(),
        c.judged_alpha,
        c.exact_texel_point[0],
        c.exact_texel_point[1],
        if texels.is_empty() { "the border".into() } else { texels.join(", ") },
        c.exact_alpha,
        if c.exact_opaque { "opaque" } else { "transparent" },
    )
}

/// The device as `render.json` names it: names, versions, the ray tracing
/// extensions it has and those `enabled` for this run.
pub(super) fn device_json(info: &DeviceInfo, enabled: Features) -> Value {
    let has = info.has;
    json!({
        "index": info.index,
        "name": info.name,
        "driver_name": info.driver_name,
        "driver_info": info.driver_info,
        "driver_version": info.driver_version_text(),
        "driver_version_raw": info.driver_version,
        "vendor_id": format!("0x{:04x}", info.vendor_id),
        "device_id": format!("0x{:04x}", info.device_id),
        "vulkan_api_version": info.api_version_text(),
        "extensions": {
            "VK_KHR_acceleration_structure": has.acceleration_structure,
            "VK_KHR_ray_query": has.ray_query,
            "VK_KHR_ray_tracing_pipeline": has.ray_tracing_pipeline,
            "VK_EXT_opacity_micromap": has.opacity_micromap,
            "VK_KHR_opacity_micromap": info.khr_opacity_micromap,
        },
        "enabled_extensions": enabled.names(),
        "max_micromap_levels": info.max_micromap_levels.map(|[two, four]| json!({"2-state": two, "4-state": four})),
        "sampler_lookup": {
            "runtimeDescriptorArray_and_shaderSampledImageArrayNonUniformIndexing": info.sampler_lookup,
            "samplerMirrorClampToEdge": info.mirror_clamp_to_edge,
        },
    })
}

/// One mesh's micromap levels as JSON and as a line (`12 x L3 4-state, 2
/// special`).
pub(super) fn levels(name: &str, triangles: usize, counts: &LevelCounts) -> (Value, String) {
    let mut parts: Vec<String> = counts
        .levels
        .iter()
        .map(|(&(level, states), n)| format!("{n} x L{level} {states}-state"))
        .collect();
    if counts.special > 0 {
        parts.push(format!("{} special", counts.special));
    }
    let value = json!({
        "mesh": name,
        "triangles": triangles,
        "special": counts.special,
        "levels": counts.levels.iter().map(|(&(level, states), n)| json!({"level": level, "states": states, "triangles": n})).collect::<Vec<_>>(),
    });
    (value, format!("{name}: {}", parts.join(", ")))
}
