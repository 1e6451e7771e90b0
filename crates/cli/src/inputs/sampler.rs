//! The sampler, cutoff and model options `bake`, `verify-bake` and `render`
//! share: each enum name is the library's (`FromStr`/`Display`), only the
//! flag and the rejected text are put before its message here.

use super::flags;
use cli_support::args::Parsed;
use cli_support::output::Failure;
use micromap_index::bake::mesh::MeshOptions;
use micromap_index::bake::{AddressMode, Comparison, Filter, Model, TextureUnit};

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

/// The texture-unit flags ([`flags::TEXTURE_UNIT`]), each checked by the
/// library's ranges (default: the library's default unit).
pub(crate) fn texture_unit_option(p: &Parsed<'_>) -> Result<TextureUnit, Failure> {
    let mut unit = TextureUnit::default();
    if let Some(text) = p.get("--subtexel-bits") {
        let k = text
            .parse::<u32>()
            .ok()
            .filter(|_| text.bytes().all(|b| b.is_ascii_digit()))
            .ok_or_else(|| {
                Failure::Malformed(format!("--subtexel-bits {text:?}: expected 4..=16"))
            })?;
        unit = unit.with_subtexel_bits(k);
    }
    if let Some(text) = p.get("--interpolation") {
        let interpolation = text
            .parse()
            .map_err(|e| Failure::Malformed(format!("--interpolation {text:?}: {e}")))?;
        unit = unit.with_interpolation(interpolation);
    }
    if let Some(text) = p.get("--filter-error") {
        let error = text.parse::<f32>().map_err(|_| {
            Failure::Malformed(format!(
                "--filter-error {text:?}: expected a number in [0, 1]"
            ))
        })?;
        unit = unit.with_filter_error(error);
    }
    if let Some(text) = p.get("--linear") {
        let rule = text
            .parse()
            .map_err(|e| Failure::Malformed(format!("--linear {text:?}: {e}")))?;
        unit = unit.with_linear_rule(rule);
    }
    unit.check().map_err(|e| Failure::Malformed(e.to_string()))
}

/// A texture unit as the JSON reports write it (`summary.json`,
/// `verify-bake --json`): which model judged.
#[derive(serde::Serialize)]
pub(crate) struct TextureUnitJson {
    subtexel_bits: u32,
    interpolation: &'static str,
    /// The binary32 value exactly (as `f64`: `2^-16` prints as
    /// `1.52587890625e-5`, not the shortest binary32 text).
    filter_error: f64,
    linear: &'static str,
}

impl From<TextureUnit> for TextureUnitJson {
    fn from(unit: TextureUnit) -> Self {
        TextureUnitJson {
            subtexel_bits: unit.subtexel_bits,
            interpolation: unit.interpolation.name(),
            filter_error: f64::from(unit.filter_error),
            linear: unit.linear.name(),
        }
    }
}

/// What judges known states, from the flags: the model and the texture
/// unit, as the options a bake or a verification takes.
pub(crate) fn judge_option(p: &Parsed<'_>) -> Result<MeshOptions, Failure> {
    Ok(MeshOptions {
        model: model_option(p)?,
        texture_unit: texture_unit_option(p)?,
        ..MeshOptions::default()
    })
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
