//! The scene reference (`activemuscle keys`, committed as `docs/scene-reference.md`), generated
//! from the code so that it cannot go stale:
//!
//! - the keys of each table are the ones serde accepts: the field list a derived `Deserialize`
//!   hands to its deserializer, read by [`keys_of`] without parsing anything;
//! - what each key is (its unit, default and allowed values) is its field's doc comment, read
//!   from the spec's source compiled into the binary ([`SOURCES`]); its type is the field's;
//! - the energies, active curves, approaches, laws, couplings, elements, volumetric forms and
//!   study kinds come from their registries, with their parameters (unit, default, range).
//!
//! A test compares the committed page with [`markdown`]; another checks that every key has a
//! doc comment (a new spec's file goes into [`SOURCES`]).

use crate::active::{Approach, CURVES};
use crate::energy::SHIPPED;
use crate::fem::element::Element;
use crate::models::{
    ActivationSpec, CouplingKind, ExplicitSpec, IncompressibilityKind, IncompressibilitySpec,
    LawKind,
};
use crate::parameter::Parameter;
use crate::studies::{StudyKind, StudySpec};
use serde::de::{self, Deserialize, Deserializer, Visitor};
use std::fmt::{self, Write as _};

/// The source files that declare scene keys, compiled in: their fields' doc comments are the
/// reference's descriptions.
pub const SOURCES: &[&str] = &[
    include_str!("mod.rs"),
    include_str!("../models/activation.rs"),
    include_str!("../models/spec.rs"),
    include_str!("../models/formula.rs"),
    include_str!("../active/drive.rs"),
    include_str!("../studies/uniaxial.rs"),
    include_str!("../studies/cylinder.rs"),
    include_str!("../studies/fit/mod.rs"),
    include_str!("../studies/stability.rs"),
    include_str!("../studies/tradeoff/mod.rs"),
    include_str!("../studies/history.rs"),
    include_str!("../studies/shear.rs"),
    include_str!("../studies/biaxial.rs"),
    include_str!("../studies/tangent.rs"),
    include_str!("../studies/tangent/fe.rs"),
];

/// A table of a scene: its name in the file, the spec type's name and the keys serde accepts.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// How a scene writes it (`[activation]`, `[[study]] kind = "cylinder"`).
    pub heading: String,
    /// The spec type (`CylinderSpec`), whose source documents the keys.
    pub spec: &'static str,
    /// Its keys, in the spec's order.
    pub keys: &'static [&'static str],
}

/// One key: its name, its type as written in a scene and its doc comment.
#[derive(Debug, Clone, PartialEq)]
pub struct Key {
    /// Name in the scene.
    pub name: &'static str,
    /// Type in scene terms (`number`, `list of numbers`, …).
    pub kind: String,
    /// The field's doc comment, one paragraph (empty: undocumented).
    pub doc: String,
}

/// Ends a probe: nothing is read.
#[derive(Debug)]
struct ProbeEnd;

impl fmt::Display for ProbeEnd {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("probe")
    }
}

impl std::error::Error for ProbeEnd {}

impl de::Error for ProbeEnd {
    fn custom<T: fmt::Display>(_msg: T) -> Self {
        ProbeEnd
    }
}

/// A deserializer that records the name and fields a derived `Deserialize` asks for, and
/// stops there.
struct Probe<'a>(&'a mut Option<(&'static str, &'static [&'static str])>);

impl<'de> Deserializer<'de> for Probe<'_> {
    type Error = ProbeEnd;

    fn deserialize_any<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, ProbeEnd> {
        Err(ProbeEnd)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, ProbeEnd> {
        *self.0 = Some((name, fields));
        Err(ProbeEnd)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        name: &'static str,
        variants: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, ProbeEnd> {
        *self.0 = Some((name, variants));
        Err(ProbeEnd)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map identifier ignored_any
    }
}

/// The spec type's name and keys of a derived `Deserialize` (`None`: written by hand); for a
/// derived enum, its name and the names of its variants.
pub fn keys_of<'de, T: Deserialize<'de>>() -> Option<(&'static str, &'static [&'static str])> {
    let mut seen = None;
    let _ = T::deserialize(Probe(&mut seen));
    seen
}

/// Every table of a scene whose keys serde lists: `[activation]`, its inline tables,
/// `[incompressibility]`, then each study kind of the registry and the tables inside studies.
pub fn tables() -> Vec<Table> {
    let mut out = Vec::new();
    let mut push = |heading: String, probed: Option<(&'static str, &'static [&'static str])>| {
        if let Some((spec, keys)) = probed {
            out.push(Table {
                heading,
                spec,
                keys,
            });
        }
    };
    push("[activation]".into(), keys_of::<ActivationSpec>());
    push(
        "[activation] explicit = { … }".into(),
        keys_of::<ExplicitSpec>(),
    );
    push(
        "[activation] force_velocity = { … }".into(),
        keys_of::<crate::active::ForceVelocity>(),
    );
    push(
        "[incompressibility]".into(),
        keys_of::<IncompressibilitySpec>(),
    );
    for &kind in StudyKind::ALL {
        let mut seen = None;
        let _ = StudySpec::of_kind(kind, Probe(&mut seen));
        push(format!("[[study]] kind = \"{}\"", kind.name()), seen);
    }
    push(
        "[[study.regions]] (cylinder)".into(),
        keys_of::<crate::studies::cylinder::RegionSpec>(),
    );
    push(
        "motor_units = [{ … }] (activation-in-time)".into(),
        keys_of::<crate::studies::history::MotorUnitSpec>(),
    );
    push(
        "h = { … } (tangent)".into(),
        keys_of::<crate::studies::tangent::StepsSpec>(),
    );
    push(
        "fe = { … } (tangent)".into(),
        keys_of::<crate::studies::tangent::FeSpec>(),
    );
    out
}

/// The doc comment and type of field `key` of struct `spec` in [`SOURCES`] (`None`: not found).
pub fn field(spec: &str, key: &str) -> Option<(String, String)> {
    SOURCES.iter().find_map(|source| {
        let start = struct_position(source, spec)?;
        field_in(&source[start..], key)
    })
}

/// Where `struct <spec>` is declared in `source`.
fn struct_position(source: &str, spec: &str) -> Option<usize> {
    let pattern = format!("struct {spec}");
    source.match_indices(&pattern).find_map(|(i, _)| {
        let next = source[i + pattern.len()..].chars().next()?;
        (!next.is_alphanumeric() && next != '_').then_some(i)
    })
}

/// The first field declaration `[pub] key: Type,` (or a field renamed to `key`) after the
/// start of `source`, with the doc lines above it.
fn field_in(source: &str, key: &str) -> Option<(String, String)> {
    let lines: Vec<&str> = source.lines().collect();
    let renamed = format!("rename = \"{key}\"");
    let mut pending_rename = false;
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        if t.starts_with("#[serde(") && t.contains(&renamed) {
            pending_rename = true;
            continue;
        }
        let declared = t
            .strip_prefix("pub ")
            .unwrap_or(t)
            .split_once(": ")
            .filter(|(name, _)| {
                name.chars().all(|c| c.is_alphanumeric() || c == '_') && !name.is_empty()
            });
        let Some((name, ty)) = declared else {
            continue;
        };
        if name != key && !pending_rename {
            continue;
        }
        let mut doc = Vec::new();
        // Attributes (`#[serde(...)]`, also over several lines) between the doc and the field.
        let mut in_attribute = false;
        for above in lines[..i].iter().rev() {
            let a = above.trim();
            if in_attribute {
                in_attribute = !a.starts_with("#[");
            } else if let Some(d) = a.strip_prefix("///") {
                doc.push(d.trim());
            } else if a.ends_with(")]") && !a.starts_with("#[") {
                in_attribute = true;
            } else if !a.starts_with("#[") {
                break;
            }
        }
        doc.reverse();
        let ty = ty.trim_end_matches(',').trim().to_string();
        return Some((doc.join(" "), ty));
    }
    None
}

/// The names a field of enum type `rust` (its type as written in the source) takes, from the
/// enum's derived `Deserialize` or its registry; `None`: not an enum of names.
fn variants(rust: &str) -> Option<Vec<&'static str>> {
    use crate::studies::{biaxial, fit, tradeoff};
    let probed = match rust {
        "LawKind" => keys_of::<LawKind>(),
        "CouplingKind" => keys_of::<CouplingKind>(),
        "FrozenTangent" => keys_of::<crate::active::FrozenTangent>(),
        "BelowMinimum" => keys_of::<crate::active::BelowMinimum>(),
        "RepresentationKind" => keys_of::<crate::models::RepresentationKind>(),
        "IncompressibilityKind" => keys_of::<IncompressibilityKind>(),
        "Direction" => keys_of::<crate::uniaxial::Direction>(),
        "FitKind" => keys_of::<fit::FitKind>(),
        "StressKind" => keys_of::<fit::StressKind>(),
        "ExplicitTarget" => keys_of::<crate::fit::ExplicitTarget>(),
        "Method" => keys_of::<crate::fit::solver::Method>(),
        "Interpolation" => keys_of::<crate::active::time::Interpolation>(),
        "BiaxialPath" => keys_of::<biaxial::BiaxialPath>(),
        "OptionGroup" => keys_of::<tradeoff::OptionGroup>(),
        "Approach" => return Some(Approach::NAMES.to_vec()),
        "ActivationMap" => {
            return Some(
                crate::active::ActivationMap::NAMED
                    .iter()
                    .map(|m| m.name())
                    .collect(),
            )
        }
        "Element" => return Some(Element::ALL.iter().map(|e| e.name()).collect()),
        _ => None,
    };
    probed.map(|(_, names)| names.to_vec())
}

fn quoted(names: &[&str]) -> String {
    let v: Vec<String> = names.iter().map(|n| format!("`\"{n}\"`")).collect();
    v.join(", ")
}

/// A Rust field type in a scene's terms.
fn scene_type(rust: &str) -> String {
    let t = rust.replace(' ', "");
    let t = t
        .strip_prefix("Option<")
        .and_then(|s| s.strip_suffix('>'))
        .unwrap_or(&t);
    let listed = t.strip_prefix("Vec<").and_then(|s| s.strip_suffix('>'));
    if let Some(names) = variants(t) {
        return format!("one of {}", quoted(&names));
    }
    if let Some(names) = listed.and_then(variants) {
        return format!("list of {}", quoted(&names));
    }
    match t {
        "f64" => "number".into(),
        "i64" | "usize" | "u32" | "u64" => "integer".into(),
        "bool" => "boolean".into(),
        "String" => "string".into(),
        "Vec<f64>" => "list of numbers".into(),
        "Vec<String>" => "list of strings".into(),
        "[f64;2]" => "[number, number]".into(),
        "[f64;3]" => "[number, number, number]".into(),
        "Vec<[f64;2]>" => "list of [number, number]".into(),
        "Vec<[i64;2]>" => "list of [integer, integer]".into(),
        "Vec<Vec<f64>>" => "list of lists of numbers".into(),
        "StretchSpec" => "list of numbers, or { from, to, step, extra }".into(),
        "LoadingSpec" => "number, list of [t, λ], or `\"free\"`".into(),
        "EnergySpec" => "table: energy = \"name\" and its parameters".into(),
        "Vec<EnergySpec>" => "list of tables: energy = \"name\" and its parameters".into(),
        "BTreeMap<String,f64>" => "table: name = number".into(),
        "BTreeMap<String,[f64;2]>" => "table: name = [number, number]".into(),
        "Bases" => quoted(&["clamped", "sliding"]).replace(", ", " or "),
        _ => match listed {
            Some(_) => "list of tables".into(),
            None => "table".into(),
        },
    }
}

/// A doc comment as Markdown table text: rustdoc's escapes and links undone, pipes escaped.
fn cell(doc: &str) -> String {
    doc.replace("\\[", "[")
        .replace("\\]", "]")
        .replace("[`", "`")
        .replace("`]", "`")
        .replace('|', "\\|")
}

/// The keys of `table` with their types and doc comments.
pub fn keys(table: &Table) -> Vec<Key> {
    table
        .keys
        .iter()
        .map(|&name| {
            let (doc, ty) = field(table.spec, name).unwrap_or_default();
            Key {
                name,
                kind: scene_type(&ty),
                doc,
            }
        })
        .collect()
}

fn number(x: f64) -> String {
    if x == f64::INFINITY {
        "∞".into()
    } else if x == f64::NEG_INFINITY {
        "−∞".into()
    } else {
        crate::text::shortest(x)
    }
}

fn parameter_table(h: &mut String, parameters: &[Parameter]) {
    h.push_str("| parameter | symbol | unit | default | range |\n|---|---|---|---|---|\n");
    for p in parameters {
        let default = p.default.map_or("(required)".into(), number);
        let _ = writeln!(
            h,
            "| `{}` | {} | {} | {} | [{}, {}] |",
            p.name,
            p.symbol,
            p.unit,
            default,
            number(p.range.0),
            number(p.range.1)
        );
    }
}

fn key_table(h: &mut String, table: &Table) {
    h.push_str("| key | type | what |\n|---|---|---|\n");
    for k in keys(table) {
        let _ = writeln!(h, "| `{}` | {} | {} |", k.name, k.kind, cell(&k.doc));
    }
    h.push('\n');
}

fn names<T: Copy>(all: &[T], name: impl Fn(T) -> &'static str) -> String {
    let v: Vec<String> = all.iter().map(|&x| format!("`{}`", name(x))).collect();
    v.join(", ")
}

fn material_section(h: &mut String) {
    h.push_str("## `[material]`\n\n");
    h.push_str(
        "| key | type | what |\n|---|---|---|\n\
         | `energy` | name | the passive energy, one of the table below (default: the first) |\n\
         | *its parameters* | number | by name, flat beside `energy`; a parameter left out takes its default |\n\
         | `fibre` | [number, number, number] | fibre direction m in the reference configuration, normalised (default [1, 0, 0]) |\n\n",
    );
    formula_section(h);
    for e in SHIPPED {
        let _ = writeln!(h, "### `energy = \"{}\"`\n\n{}\n", e.name, cell(e.formula));
        if !e.chapter.is_empty() {
            let _ = writeln!(h, "Chapter: {}.\n", e.chapter);
        }
        parameter_table(h, e.parameters);
        h.push('\n');
    }
}

/// `energy = "formula"`: its keys (the fields of `FormulaSpec`, read by hand) and the keys of a
/// declared parameter.
fn formula_section(h: &mut String) {
    let doc = |field_name: &str| {
        field("FormulaSpec", field_name).map_or(String::new(), |(d, _)| cell(&d))
    };
    let _ = writeln!(
        h,
        "### `energy = \"{}\"`\n\nYour own energy, written as a formula of the invariants in the \
         scene ([user-energy.md](user-energy.md)).\n\n| key | type | what |\n|---|---|---|\n\
         | `W` | string | {} |\n| `name` | string | {} |\n\
         | `parameters` | table: name = number or {{ … }} | {} |\n",
        crate::energy::FORMULA,
        doc("formula"),
        doc("name"),
        doc("parameters")
    );
    if let Some((spec, keys)) = keys_of::<crate::models::formula::DeclaredSpec>() {
        h.push_str("A declared parameter, `[material.parameters] name = { … }`:\n\n");
        key_table(
            h,
            &Table {
                heading: "[material.parameters]".into(),
                spec,
                keys,
            },
        );
    }
}

fn activation_section(h: &mut String, tables: &[Table]) {
    h.push_str("## `[activation]`\n\n");
    for t in tables
        .iter()
        .filter(|t| t.heading.starts_with("[activation]"))
    {
        if t.heading != "[activation]" {
            let _ = writeln!(h, "### `{}`\n", t.heading);
        }
        key_table(h, t);
    }
    let _ = writeln!(
        h,
        "Laws: {}. Couplings: {}. Which keys apply to which approach: \
         [approaches.md](approaches.md).\n",
        names(&LawKind::ALL, LawKind::name),
        names(&CouplingKind::ALL, CouplingKind::name)
    );
    h.push_str("### Approaches (`approach = \"…\"`)\n\n");
    h.push_str(
        "| approach | activation variable | laws | couplings | maps |\n|---|---|---|---|---|\n",
    );
    for &a in Approach::ALL {
        let maps: Vec<String> = a.maps().iter().map(|m| format!("`{}`", m.name())).collect();
        let _ = writeln!(
            h,
            "| `{}` | {} | {} | {} | {} |",
            a.name(),
            a.variable().unwrap_or("none"),
            or_none(names(a.laws(), LawKind::name)),
            or_none(names(a.couplings(), CouplingKind::name)),
            or_none(maps.join(", "))
        );
    }
    h.push('\n');
    h.push_str(
        "### Active curves (`curve = \"…\"`)\n\nA curve's parameters are keys of \
         `[activation]`, flat beside `curve`.\n\n",
    );
    for c in CURVES {
        let _ = writeln!(h, "#### `curve = \"{}\"`\n\n{}\n", c.name, cell(c.formula));
        parameter_table(h, c.parameters);
        h.push('\n');
    }
}

fn or_none(s: String) -> String {
    if s.is_empty() {
        "none".into()
    } else {
        s
    }
}

fn studies_section(h: &mut String, tables: &[Table]) {
    h.push_str("## `[[study]]`\n\n");
    let _ = writeln!(
        h,
        "A scene holds any number of studies, each a `[[study]]` table with its `kind`: {}. \
         A key a kind does not take is an error that lists the kind's keys. Elements \
         (`element` of a cylinder study): {}.\n",
        names(StudyKind::ALL, StudyKind::name),
        names(&Element::ALL, Element::name)
    );
    // The kinds, then the tables inside studies (`… (kind)`).
    let kinds = tables.iter().filter(|t| t.heading.starts_with("[[study]]"));
    let inside = tables.iter().filter(|t| t.heading.ends_with(')'));
    for t in kinds.chain(inside) {
        let _ = writeln!(h, "### `{}`\n", t.heading);
        key_table(h, t);
    }
}

fn index_section(h: &mut String, tables: &[Table]) {
    h.push_str("## Which study kinds take a key\n\n| key | kinds |\n|---|---|\n");
    let kinds: Vec<&Table> = tables
        .iter()
        .filter(|t| t.heading.starts_with("[[study]]"))
        .collect();
    let mut all: Vec<&str> = kinds.iter().flat_map(|t| t.keys.iter().copied()).collect();
    all.sort_unstable();
    all.dedup();
    for key in all {
        let takers: Vec<String> = kinds
            .iter()
            .filter(|t| t.keys.contains(&key))
            .map(|t| {
                t.heading
                    .trim_start_matches("[[study]] kind = ")
                    .trim_matches('"')
                    .to_string()
            })
            .collect();
        let _ = writeln!(h, "| `{key}` | {} |", takers.join(", "));
    }
}

/// The whole reference as Markdown (what `activemuscle keys` prints).
pub fn markdown() -> String {
    let tables = tables();
    let mut h = String::from(
        "# Scene reference\n\n\
         Every key a scene file takes, generated from the code by `activemuscle keys` (the keys \
         are those the scene reader accepts, each described by its field's documentation; the \
         energies, curves, approaches, laws and kinds come from their registries). A test fails \
         when this page differs from what the code generates: regenerate it with \
         `cargo run --release -- keys > docs/scene-reference.md`.\n\n\
         A scene is a TOML file: `[material]`, `[activation]`, an optional \
         `[incompressibility]` and any number of `[[study]]` tables, plus an optional \
         `title`. Every key is optional unless marked required; `activemuscle check SCENE` \
         prints the scene with every default written out. Units: stresses and energies in kPa, \
         stretches dimensionless, times in s, lengths in any consistent unit.\n\n",
    );
    material_section(&mut h);
    activation_section(&mut h, &tables);
    h.push_str("## `[incompressibility]`\n\n");
    for t in tables.iter().filter(|t| t.heading == "[incompressibility]") {
        key_table(&mut h, t);
    }
    let forms = keys_of::<IncompressibilityKind>().map_or(&[][..], |(_, v)| v);
    let _ = writeln!(
        h,
        "Volumetric forms (`kind`): {}; the equations, and what 4C and FEBio call them: \
         [other-codes.md](other-codes.md).\n",
        names(forms, |f| f)
    );
    studies_section(&mut h, &tables);
    index_section(&mut h, &tables);
    h
}
