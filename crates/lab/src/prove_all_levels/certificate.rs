//! The explored product as a certificate for an independent checker
//! (`micromap-lab prove --all-levels --certificate FILE`, checked by
//! `crates/lab/certificates/product.py`; docs/verification.md 10.11).
//!
//! The certificate says, for every state, what it claims about the point
//! (the remainders after the columns read, the walk's local coordinates as
//! forms in them and its flags, the reference's parity and guess), which
//! start leads to it, and for every transition the column read, the two
//! digits and the target. The checker trusts none of it: it proves each
//! transition from its own model of `Walk::step` and of the reference's
//! digits (one z3 query per transition), recomputes which states a point
//! can reach and requires a start or transition for each.

#[allow(clippy::wildcard_imports)]
use super::*;
use serde::Serialize;
use std::fmt::Write as _;

/// The certificate's format version (the checker refuses others).
pub const CERTIFICATE_FORMAT: u32 = 1;

#[derive(Serialize)]
struct RestJson {
    sum: u8,
    zero: String,
}

impl From<Rest> for RestJson {
    fn from(rest: Rest) -> RestJson {
        RestJson {
            sum: rest.sum,
            zero: coordinates(rest.zero),
        }
    }
}

#[derive(Serialize)]
struct WalkJson {
    u: [i32; 3],
    v: [i32; 3],
    w: [i32; 3],
    mid_flip: bool,
    top_flip: bool,
}

#[derive(Serialize)]
struct ReferenceJson {
    parity: u8,
    minus_one_on: &'static str,
    u_zero: bool,
    w_zero: bool,
}

#[derive(Serialize)]
struct StateJson {
    id: usize,
    rest: RestJson,
    walk: WalkJson,
    reference: ReferenceJson,
}

#[derive(Serialize)]
struct StartJson {
    bits: String,
    rest: RestJson,
    minus_one_on: &'static str,
    state: usize,
}

#[derive(Serialize)]
struct TransitionJson {
    from: usize,
    bits: String,
    rest: RestJson,
    to: usize,
    walk_digit: u8,
    reference_digit: u8,
}

/// `uvw`-style names of the set flags, `-` for none.
fn coordinates(flags: [bool; 3]) -> String {
    let names: String = ["u", "v", "w"]
        .iter()
        .zip(flags)
        .filter_map(|(name, set)| set.then_some(*name))
        .collect();
    if names.is_empty() {
        "-".into()
    } else {
        names
    }
}

/// The bits of `u`, `v`, `w` as `0`/`1` characters.
fn bit_string(bits: [bool; 3]) -> String {
    bits.iter().map(|&b| if b { '1' } else { '0' }).collect()
}

fn coordinate_name(c: Option<usize>) -> &'static str {
    c.map_or("-", |c| ["u", "v", "w"][c])
}

fn form(f: Form) -> [i32; 3] {
    [f.ru, f.rv, f.constant]
}

/// One JSON object per line, so a change shows as a one-line diff.
fn push_items<T: Serialize>(out: &mut String, key: &str, items: &[T], last: bool) {
    let _ = writeln!(out, "  \"{key}\": [");
    for (i, item) in items.iter().enumerate() {
        // Plain structs of numbers, strings and booleans always serialize.
        let line = serde_json::to_string(item).unwrap_or_default();
        let comma = if i + 1 < items.len() { "," } else { "" };
        let _ = writeln!(out, "    {line}{comma}");
    }
    out.push_str(if last { "  ]\n" } else { "  ],\n" });
}

impl AllLevelsReport {
    /// The explored product as a certificate (JSON, one state, start or
    /// transition per line), or `None` unless the search proved the walk:
    /// a search that stopped early has no complete product to certify.
    ///
    /// ```
    /// use micromap_index_lab::prove::WalkVersion;
    /// use micromap_index_lab::prove_all_levels::prove_all_levels;
    /// let report = prove_all_levels(WalkVersion::Version2).unwrap();
    /// let certificate = report.certificate().unwrap();
    /// assert!(certificate.contains("\"transitions\": ["));
    /// let refuted = prove_all_levels(WalkVersion::Version1).unwrap();
    /// assert!(refuted.certificate().is_none());
    /// ```
    #[must_use]
    pub fn certificate(&self) -> Option<String> {
        if !self.is_proof() {
            return None;
        }
        let walk = self.walk.map_or("mutated", WalkVersion::name);
        let states: Vec<StateJson> = self
            .product_states
            .iter()
            .enumerate()
            .map(|(id, s)| StateJson {
                id,
                rest: s.rest.into(),
                walk: WalkJson {
                    u: form(s.walk.u),
                    v: form(s.walk.v),
                    w: form(s.walk.w),
                    mid_flip: s.walk.mid_flip,
                    top_flip: s.walk.top_flip,
                },
                reference: ReferenceJson {
                    parity: u8::from(s.reference.parity),
                    minus_one_on: coordinate_name(s.reference.decremented),
                    u_zero: s.reference.u_zero,
                    w_zero: s.reference.w_zero,
                },
            })
            .collect();
        let starts: Vec<StartJson> = self
            .starts
            .iter()
            .enumerate()
            .filter_map(|(state, start)| {
                start.map(|start| StartJson {
                    bits: bit_string(start.column.bits),
                    rest: start.column.rest.into(),
                    minus_one_on: coordinate_name(start.decremented),
                    state,
                })
            })
            .collect();
        let transitions: Vec<TransitionJson> = self
            .transitions
            .iter()
            .map(|t| TransitionJson {
                from: t.from,
                bits: bit_string(t.column.bits),
                rest: t.column.rest.into(),
                to: t.to,
                walk_digit: t.walk_digit,
                reference_digit: t.reference_digit,
            })
            .collect();
        let mut out = String::from("{\n");
        let _ = writeln!(out, "  \"format\": {CERTIFICATE_FORMAT},");
        let _ = writeln!(
            out,
            "  \"claim\": \"the {walk} walk equals the reference at every dyadic point of the \
             closed triangle and every level (docs/verification.md 10.11)\","
        );
        out.push_str(
            "  \"written_by\": \"micromap-lab prove --all-levels --certificate FILE\",\n  \
             \"checked_by\": \"python3 crates/lab/certificates/product.py FILE\",\n  \
             \"forms\": \"[a, b, c] is a Ru + b Rv + c, Ru and Rv the remainders frac(2^k u), \
             frac(2^k v) after the k columns read; bits are u v w\",\n",
        );
        push_items(&mut out, "states", &states, false);
        push_items(&mut out, "starts", &starts, false);
        push_items(&mut out, "transitions", &transitions, true);
        out.push_str("}\n");
        Some(out)
    }
}
