//! The sampler, cutoff and model options `bake`, `verify-bake` and `render`
//! share: each enum name is the library's (`FromStr`/`Display`), only the
//! flag and the rejected text are put before its message here.

use super::flags;
use cli_support::args::Parsed;
use cli_support::output::Failure;
use micromap_index::bake::{AddressMode, Comparison, Filter, Model};

/// `--address*` as an address mode, or the library's message prefixed
/// with the rejected text.
fn parse_address(text: &str) -> Result<AddressMode, Failure> {
    text.parse()
        .map_err(|e| Failure::Malformed(format!("address mode {text:?}: {e}")))
}

fn parse_f32(name: &str, text: &str) -> Result<f32, Failure> {
    match text.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(Failure::Malformed(format!(
            "{name} {text:?}: expected a finite number"
        ))),
    }
}

/// The sampler and cutoff options shared by both commands; `None` fields
/// keep the asset's own (glTF) or the default.
pub(crate) struct SamplerOptions {
    pub(super) filter: Option<Filter>,
    pub(super) address_u: Option<AddressMode>,
    pub(super) address_v: Option<AddressMode>,
    pub(super) border: f32,
    pub(super) cutoff: Option<f32>,
    pub(super) comparison: Comparison,
}

pub(crate) fn sampler_options(p: &Parsed<'_>) -> Result<SamplerOptions, Failure> {
    let filter = p
        .get("--filter")
        .map(|text| {
            text.parse::<Filter>()
                .map_err(|e| Failure::Malformed(format!("--filter {text:?}: {e}")))
        })
        .transpose()?;
    let both = p.get("--address").map(parse_address).transpose()?;
    let address_u = p
        .get("--address-u")
        .map(parse_address)
        .transpose()?
        .or(both);
    let address_v = p
        .get("--address-v")
        .map(parse_address)
        .transpose()?
        .or(both);
    let border = p
        .get("--border")
        .map(|t| parse_f32("--border", t))
        .transpose()?
        .unwrap_or(0.0);
    let cutoff = p
        .get("--cutoff")
        .map(|t| parse_f32("--cutoff", t))
        .transpose()?;
    if let Some(c) = cutoff {
        if !(0.0..=1.0).contains(&c) {
            return Err(Failure::Malformed(format!(
                "--cutoff {c}: expected an alpha in [0, 1]"
            )));
        }
    }
    Ok(SamplerOptions {
        filter,
        address_u,
        address_v,
        border,
        cutoff,
        comparison: if p.flag("--opaque-above") {
            Comparison::Above
        } else {
            Comparison::AtLeast
        },
    })
}

/// `--model` (default gpu-binary32).
pub(crate) fn model_option(p: &Parsed<'_>) -> Result<Model, Failure> {
    match p.get("--model") {
        None => Ok(Model::default()),
        Some(text) => text
            .parse()
            .map_err(|e| Failure::Malformed(format!("--model {text:?}: {e}"))),
    }
}

/// The sampler and cutoff flags (every sampler flag but `--model`) are
/// refused with `what`: they would bake (or check) micromaps for another
/// sampling than the one the asset's renderer does.
pub(crate) fn refuse_overrides(p: &Parsed<'_>, what: &str) -> Result<(), Failure> {
    let mut overrides = flags::SAMPLER
        .iter()
        .map(|flag| flag.name)
        .filter(|&name| name != "--model");
    if let Some(flag) = overrides.find(|f| p.get(f).is_some() || p.flag(f)) {
        return Err(Failure::Usage(format!(
            "{flag} with {what}: the micromaps must match the asset's own samplers and \
             alphaCutoff, which the renderer uses"
        )));
    }
    Ok(())
}
