//! `render`'s options beyond the shared ones, each checked before any
//! setup: counts, the picture size, the camera, the tracers, the lookups,
//! the methods,
//! the device, the fault and the report's length.

use cli_support::args::Parsed;
use cli_support::output::Failure;
use micromap_index_render::vulkan::DeviceSelector;
use micromap_index_render::{Camera, Faults, Lookup, Method, Tracer};

pub(super) fn count(p: &Parsed<'_>, name: &str, default: u32, max: u32) -> Result<u32, Failure> {
    match p.get(name) {
        None => Ok(default),
        Some(text) => match text.parse::<u32>() {
            Ok(n) if (1..=max).contains(&n) && text.bytes().all(|b| b.is_ascii_digit()) => Ok(n),
            _ => Err(Failure::Malformed(format!(
                "{name} {text:?}: expected a count 1..={max}"
            ))),
        },
    }
}

pub(super) fn size(p: &Parsed<'_>) -> Result<(u32, u32), Failure> {
    let text = p.get("--size").unwrap_or("256x256");
    let parsed = text.split_once('x').and_then(|(w, h)| {
        let n = |t: &str| {
            t.bytes()
                .all(|b| b.is_ascii_digit())
                .then(|| t.parse::<u32>().ok())
                .flatten()
        };
        Some((n(w)?, n(h)?))
    });
    match parsed {
        Some((w, h))
            if w > 0
                && h > 0
                && u64::from(w) * u64::from(h) <= micromap_index_render::MAX_PIXELS =>
        {
            Ok((w, h))
        }
        _ => Err(Failure::Malformed(format!(
            "--size {text:?}: expected WxH with at least one pixel and at most {} pixels",
            micromap_index_render::MAX_PIXELS
        ))),
    }
}

/// `--camera`, checked before any setup; `None`: frame the scene
/// (`framing`).
pub(super) fn camera(p: &Parsed<'_>) -> Result<Option<Camera>, Failure> {
    let Some(text) = p.get("--camera") else {
        return Ok(None);
    };
    let numbers: Option<Vec<f32>> = text
        .split(',')
        .map(|t| t.trim().parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect();
    match numbers.as_deref() {
        Some(&[ex, ey, ez, tx, ty, tz]) => Ok(Some(Camera {
            eye: [ex, ey, ez],
            target: [tx, ty, tz],
            fov_y_degrees: 40.0,
        })),
        Some(&[ex, ey, ez, tx, ty, tz, fov]) => Ok(Some(Camera {
            eye: [ex, ey, ez],
            target: [tx, ty, tz],
            fov_y_degrees: fov,
        })),
        _ => Err(Failure::Malformed(format!(
            "--camera {text:?}: expected six or seven finite numbers EX,EY,EZ,TX,TY,TZ[,FOV]"
        ))),
    }
}

pub(super) fn tracers(p: &Parsed<'_>) -> Result<Vec<Tracer>, Failure> {
    match p.get("--tracer") {
        None | Some("both") => Ok(Tracer::ALL.to_vec()),
        Some(name) => Tracer::from_name(name).map(|t| vec![t]).ok_or_else(|| {
            Failure::Malformed(format!(
                "--tracer {name:?}: expected query, pipeline or both"
            ))
        }),
    }
}

/// `--lookup`: what reads the texture for the alpha test (default both).
pub(super) fn lookups(p: &Parsed<'_>) -> Result<Vec<Lookup>, Failure> {
    match p.get("--lookup") {
        None | Some("both") => Ok(Lookup::ALL.to_vec()),
        Some(name) => Lookup::from_name(name).map(|l| vec![l]).ok_or_else(|| {
            Failure::Malformed(format!(
                "--lookup {name:?}: expected shader, sampler or both"
            ))
        }),
    }
}

pub(super) fn methods(p: &Parsed<'_>) -> Result<Vec<Method>, Failure> {
    let mut chosen = vec![Method::AlphaTest];
    match p.get("--methods") {
        None => chosen.extend(&Method::EMULATED[1..]),
        Some(text) => {
            for name in text.split(',') {
                let method = Method::from_name(name).ok_or_else(|| {
                    Failure::Malformed(format!(
                        "--methods: {name:?} is not one of {}",
                        Method::ALL.map(Method::name).join(", ")
                    ))
                })?;
                if !chosen.contains(&method) {
                    chosen.push(method);
                }
            }
        }
    }
    // The forced 2-state hardware micromap is checked against flat-2-state.
    if chosen.contains(&Method::Hardware2) && !chosen.contains(&Method::Flat2) {
        chosen.push(Method::Flat2);
    }
    Ok(chosen)
}

pub(super) fn device(p: &Parsed<'_>) -> Result<Option<DeviceSelector>, Failure> {
    p.get("--device")
        .map(|text| {
            text.parse()
                .map_err(|e| Failure::Malformed(format!("--device {text:?}: {e}")))
        })
        .transpose()
}

/// `--fault`: a negative control, or none.
pub(super) fn faults(p: &Parsed<'_>) -> Result<Faults, Failure> {
    match p.get("--fault") {
        None => Ok(Faults::default()),
        Some("swap-barycentrics") => Ok(Faults {
            swap_barycentrics: true,
            ..Faults::default()
        }),
        Some("flip-known") => Ok(Faults {
            flip_known: true,
            ..Faults::default()
        }),
        Some(other) => Err(Failure::Malformed(format!(
            "--fault {other:?}: expected swap-barycentrics or flip-known"
        ))),
    }
}

/// `--max-report`: contradictions kept per method (at most 2^16).
pub(super) fn max_report(p: &Parsed<'_>) -> Result<u32, Failure> {
    Ok(p.get("--max-report")
        .map_or(Ok(20), |t| {
            t.parse::<u32>()
                .map_err(|_| Failure::Malformed(format!("--max-report {t:?}: expected a count")))
        })?
        .min(1 << 16))
}
