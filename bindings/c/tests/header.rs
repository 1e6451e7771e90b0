//! The hand-written header against the Rust side: every `extern "C"`
//! function of `src/` has a prototype in `include/micromap_index.h` with
//! the same parameter names and C types (and the header declares no
//! other), every `#[repr(C)]` struct the same fields in the same order,
//! every opaque handle a forward declaration, every `MMI_*` constant the
//! same value as its `#define`, and the version macros the crate's
//! version. CI fails here when the two drift apart.

use std::collections::BTreeMap;

const HERE: &str = env!("CARGO_MANIFEST_DIR");

fn header() -> String {
    std::fs::read_to_string(format!("{HERE}/include/micromap_index.h")).unwrap()
}

fn rust_sources() -> String {
    let mut text = String::new();
    let mut files: Vec<_> = std::fs::read_dir(format!("{HERE}/src"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for file in files {
        text += &std::fs::read_to_string(file).unwrap();
        text.push('\n');
    }
    text
}

/// C text without comments, with whitespace collapsed and none around `*`.
fn normalise(text: &str) -> String {
    let collapsed = text.split_whitespace().collect::<Vec<_>>().join(" ");
    collapsed.replace(" *", "*").replace("* ", "*")
}

fn strip_c_comments(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("/*") {
        out += &rest[..start];
        let end = rest[start..].find("*/").expect("unterminated comment") + start + 2;
        out.push(' ');
        rest = &rest[end..];
    }
    out + rest
}

/// A Rust parameter or field type as the header spells it.
fn c_type(rust: &str) -> String {
    let rust = rust.trim();
    if let Some(inner) = rust.strip_prefix("*const ") {
        return format!("const {}*", c_type(inner));
    }
    if let Some(inner) = rust.strip_prefix("*mut ") {
        return format!("{}*", c_type(inner));
    }
    let base = rust.rsplit("::").next().unwrap();
    match base {
        "f32" => "float",
        "f64" => "double",
        "u8" => "uint8_t",
        "u16" => "uint16_t",
        "u32" => "uint32_t",
        "u64" => "uint64_t",
        "i32" => "int32_t",
        "i64" => "int64_t",
        "usize" => "size_t",
        "c_char" => "char",
        "c_void" => "void",
        other => other,
    }
    .to_string()
}

/// `const uint8_t**` from `*mut *const u8` puts `const` first, as C does.
fn c_decl(rust_type: &str, name: &str) -> String {
    normalise(&format!("{} {name}", c_type(rust_type)))
}

/// Rust's `extern "C"` functions: name -> normalised prototype.
fn rust_functions(src: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (at, _) in src.match_indices("extern \"C\" fn ") {
        let rest = &src[at + "extern \"C\" fn ".len()..];
        let name = &rest[..rest.find('(').unwrap()];
        let close = rest.find(')').unwrap();
        let params = &rest[name.len() + 1..close];
        let after = &rest[close + 1..rest.find('{').unwrap()];
        let ret = after
            .trim()
            .strip_prefix("->")
            .map_or("void".to_string(), c_type);
        let params: Vec<String> = params
            .split(',')
            .map(str::trim)
            .filter(|p| !p.is_empty())
            .map(|p| {
                let (n, t) = p.split_once(':').unwrap();
                c_decl(t, n.trim())
            })
            .collect();
        let params = if params.is_empty() {
            "void".to_string()
        } else {
            params.join(", ")
        };
        out.insert(
            name.to_string(),
            normalise(&format!("{ret} {name}({params})")),
        );
    }
    out
}

/// `#[repr(C)]` structs: name -> normalised field declarations; and the
/// names of the other `pub struct`/`pub enum mmi_*` (opaque handles).
fn rust_structs(src: &str) -> (BTreeMap<String, Vec<String>>, Vec<String>) {
    let mut structs = BTreeMap::new();
    let mut opaque = Vec::new();
    let lines: Vec<&str> = src.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let line = line.trim();
        let Some(name) = line
            .strip_prefix("pub struct ")
            .or_else(|| line.strip_prefix("pub enum "))
            .and_then(|r| r.strip_suffix(" {"))
        else {
            continue;
        };
        if !name.starts_with("mmi_") {
            continue;
        }
        let repr_c = lines[i.saturating_sub(3)..i]
            .iter()
            .any(|l| l.trim() == "#[repr(C)]");
        if !repr_c {
            opaque.push(name.to_string());
            continue;
        }
        let mut fields = Vec::new();
        for field in &lines[i + 1..] {
            let field = field.trim();
            if field == "}" {
                break;
            }
            let Some(decl) = field.strip_prefix("pub ") else {
                continue;
            };
            let (n, t) = decl.trim_end_matches(',').split_once(':').unwrap();
            let t = t.trim();
            let decl = if let Some(array) = t.strip_prefix('[').and_then(|a| a.strip_suffix(']')) {
                let (elem, len) = array.split_once(';').unwrap();
                c_decl(elem, &format!("{}[{}]", n.trim(), len.trim()))
            } else {
                c_decl(t, n.trim())
            };
            fields.push(decl);
        }
        structs.insert(name.to_string(), fields);
    }
    (structs, opaque)
}

/// `pub const MMI_*` values (integers, `usize::MAX` as `SIZE_MAX`).
fn rust_constants(src: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for line in src.lines() {
        let Some(rest) = line.trim().strip_prefix("pub const MMI_") else {
            continue;
        };
        let (name, rest) = rest.split_once(':').unwrap();
        let value = rest.split_once('=').unwrap().1.trim().trim_end_matches(';');
        let value = if value == "usize::MAX" {
            "SIZE_MAX".to_string()
        } else {
            parse_int(value).to_string()
        };
        out.insert(format!("MMI_{name}"), value);
    }
    out
}

fn parse_int(text: &str) -> u64 {
    let t = text.replace('_', "");
    let t = t.trim_end_matches('u');
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16).unwrap(),
        None => t
            .parse()
            .unwrap_or_else(|_| panic!("not an integer: {text}")),
    }
}

struct Header {
    functions: BTreeMap<String, String>,
    structs: BTreeMap<String, Vec<String>>,
    opaque: Vec<String>,
    defines: BTreeMap<String, String>,
}

fn parse_header(text: &str) -> Header {
    let text = strip_c_comments(text);
    let mut defines = BTreeMap::new();
    let mut body = String::new();
    let mut continued = false;
    for line in text.lines() {
        let trimmed = line.trim();
        if continued {
            continued = trimmed.ends_with('\\');
            continue;
        }
        continued = trimmed.starts_with('#') && trimmed.ends_with('\\');
        if let Some(rest) = trimmed.strip_prefix("#define ") {
            if let Some((name, value)) = rest.split_once(' ') {
                defines.insert(name.to_string(), value.trim().to_string());
            }
        } else if !trimmed.starts_with('#') && !trimmed.starts_with("extern \"C\"") {
            body += line;
            body.push('\n');
        }
    }
    let mut structs = BTreeMap::new();
    let mut opaque = Vec::new();
    let mut functions = BTreeMap::new();
    let mut rest = body.as_str();
    while let Some(at) = rest.find("typedef struct ") {
        let head = &rest[..at];
        for statement in head.split(';') {
            function(statement, &mut functions);
        }
        let after = &rest[at + "typedef struct ".len()..];
        let end = after.find(';').unwrap();
        let brace = after.find('{');
        if brace.is_some_and(|b| b < end) {
            let brace = brace.unwrap();
            let name = after[..brace].trim().to_string();
            let close = after.find('}').unwrap();
            let fields = after[brace + 1..close]
                .split(';')
                .map(normalise)
                .filter(|f| !f.is_empty())
                .collect();
            let tail = &after[close + 1..];
            let semi = tail.find(';').unwrap();
            assert_eq!(tail[..semi].trim(), name, "typedef name of struct {name}");
            structs.insert(name, fields);
            rest = &tail[semi + 1..];
        } else {
            let names: Vec<&str> = after[..end].split_whitespace().collect();
            assert_eq!(names.len(), 2, "opaque typedef {:?}", &after[..end]);
            assert_eq!(names[0], names[1]);
            opaque.push(names[0].to_string());
            rest = &after[end + 1..];
        }
    }
    for statement in rest.split(';') {
        function(statement, &mut functions);
    }
    Header {
        functions,
        structs,
        opaque,
        defines,
    }
}

fn function(statement: &str, functions: &mut BTreeMap<String, String>) {
    let s = normalise(statement.trim().trim_start_matches('}'));
    if s.is_empty() || s.starts_with("typedef int32_t mmi_result") || s == "}" {
        return;
    }
    let open = s
        .find('(')
        .unwrap_or_else(|| panic!("not a prototype: {s:?}"));
    let name = s[..open].rsplit(['*', ' ']).next().unwrap().to_string();
    assert!(name.starts_with("mmi_"), "unexpected declaration {s:?}");
    functions.insert(name, s);
}

#[test]
fn every_function_matches_its_prototype() {
    let header = parse_header(&header());
    let rust = rust_functions(&rust_sources());
    assert!(rust.len() >= 29, "found only {} functions", rust.len());
    for (name, proto) in &rust {
        let h = header
            .functions
            .get(name)
            .unwrap_or_else(|| panic!("{name} is not declared in the header"));
        assert_eq!(h, proto, "{name}: header vs Rust");
    }
    for name in header.functions.keys() {
        assert!(
            rust.contains_key(name),
            "{name} is declared but not defined"
        );
    }
}

#[test]
fn every_struct_matches_its_declaration() {
    let header = parse_header(&header());
    let (structs, opaque) = rust_structs(&rust_sources());
    assert!(structs.len() >= 13, "found only {} structs", structs.len());
    assert_eq!(
        header.structs.keys().collect::<Vec<_>>(),
        structs.keys().collect::<Vec<_>>()
    );
    for (name, fields) in &structs {
        assert_eq!(&header.structs[name], fields, "struct {name}");
    }
    let mut opaque = opaque;
    opaque.sort();
    let mut declared = header.opaque.clone();
    declared.sort();
    assert_eq!(declared, opaque, "opaque handles");
}

#[test]
fn every_constant_matches_its_define() {
    let header = parse_header(&header());
    let rust = rust_constants(&rust_sources());
    assert!(rust.len() >= 36, "found only {} constants", rust.len());
    for (name, value) in &rust {
        let h = header
            .defines
            .get(name)
            .unwrap_or_else(|| panic!("{name} is not defined in the header"));
        let h = if h == "SIZE_MAX" {
            h.clone()
        } else {
            parse_int(h).to_string()
        };
        assert_eq!(&h, value, "{name}");
    }
    for name in header.defines.keys().filter(|n| n.starts_with("MMI_")) {
        assert!(rust.contains_key(name), "{name} has no Rust constant");
    }
}

#[test]
fn the_version_macros_are_the_crates() {
    let header = parse_header(&header());
    for (macro_name, part) in [
        (
            "MICROMAP_INDEX_VERSION_MAJOR",
            env!("CARGO_PKG_VERSION_MAJOR"),
        ),
        (
            "MICROMAP_INDEX_VERSION_MINOR",
            env!("CARGO_PKG_VERSION_MINOR"),
        ),
        (
            "MICROMAP_INDEX_VERSION_PATCH",
            env!("CARGO_PKG_VERSION_PATCH"),
        ),
    ] {
        assert_eq!(header.defines[macro_name], part, "{macro_name}");
    }
    assert_eq!(
        header.defines["MICROMAP_INDEX_VERSION_STRING"],
        format!("\"{}\"", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn the_checker_sees_a_difference() {
    // Negative controls: a changed parameter type, a swapped field and a
    // changed value are each noticed.
    let text = header();
    let changed = text.replacen(
        "mmi_result mmi_index_f32(float u, float v, uint32_t level, uint32_t *out);",
        "mmi_result mmi_index_f32(float u, float v, uint64_t level, uint32_t *out);",
        1,
    );
    assert_ne!(changed, text);
    let rust = rust_functions(&rust_sources());
    assert_ne!(
        parse_header(&changed).functions["mmi_index_f32"],
        rust["mmi_index_f32"]
    );
    let swapped = text.replacen(
        "    uint32_t level;\n    /** 1 if it has",
        "    uint32_t upright;\n    /** 1 if it has",
        1,
    );
    assert_ne!(swapped, text);
    let (structs, _) = rust_structs(&rust_sources());
    assert_ne!(
        parse_header(&swapped).structs["mmi_micro_triangle"],
        structs["mmi_micro_triangle"]
    );
    let value = text.replacen(
        "#define MMI_ERROR_PANIC 10",
        "#define MMI_ERROR_PANIC 11",
        1,
    );
    assert_ne!(value, text);
    assert_ne!(
        parse_header(&value).defines["MMI_ERROR_PANIC"],
        rust_constants(&rust_sources())["MMI_ERROR_PANIC"]
    );
}
