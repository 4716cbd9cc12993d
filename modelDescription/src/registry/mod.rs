//! The registry: every variable of the FMU declared once, in [`table`], and
//! what is generated from it.
//!
//! A declaration ([`Decl`]) holds a variable's name, value reference, type,
//! start value(s), range (with its open or closed ends), description and,
//! for a parameter, the core's parameter id and the name an engineer knows
//! it by. A pulley variable (`pulley[#].radius`, `span[#].tension`) is
//! declared once and stands for every pulley slot (`#` = 1..=[`SLOTS`]).
//! From the registry come
//!
//! * [`model_description`]: the text of `modelDescription.xml`, every slot
//!   written out, its exclusive-bounds annotation and its model structure
//!   (the file in the repository is this text, checked by a test and by
//!   `build.rs`; `cargo xtask model-description` rewrites it);
//! * [`param_list`]: the core's parameter ids with their engineering names
//!   (the `params!` invocation `src/model/param_id.rs` includes);
//! * [`param_ids`], [`param_codes`]: the ids with their variables and the
//!   codes of the coded Integers, which [`crate::param_tables`] turns into
//!   ranges, start values and the adapter's look-ups.

mod table;

use std::fmt::Write as _;

pub use table::{REGISTRY, SLOTS};

/// How a variable's value reference follows from its slot `j` (1-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vr {
    /// A variable without slots.
    Fixed(u32),
    /// A pulley's parameter or input: `100 j + offset`.
    Pulley(u32),
    /// A pulley's output: `1000 + 100 j + offset` for slots 1-6,
    /// `10000 + 100 j + offset` from slot 7 on (1700-1799 hold the probe and
    /// span arrays).
    PulleyOutput(u32),
    /// An array over the slots (`span[k].tension`): `base + j`.
    Array(u32),
}

impl Vr {
    /// The value reference in slot `j` (1-based; ignored by [`Vr::Fixed`]).
    pub fn of(self, j: usize) -> u32 {
        let j = j as u32;
        match self {
            Vr::Fixed(vr) => vr,
            Vr::Pulley(off) => 100 * j + off,
            Vr::PulleyOutput(off) if j <= 6 => 1000 + 100 * j + off,
            Vr::PulleyOutput(off) => 10000 + 100 * j + off,
            Vr::Array(base) => base + j,
        }
    }
}

/// The type of a variable: a Real with its declared type, or an Integer or
/// a Boolean.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// A Real of this `<SimpleType>`.
    Real(&'static str),
    /// An Integer.
    Integer,
    /// A Boolean.
    Boolean,
}

/// The inputs an output depends on (ModelStructure).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deps {
    /// None (`dependencies=""`); also for a variable that is no output.
    None,
    /// These inputs of its own pulley slot (`"omegaRef"`, `"torque"`).
    Own(&'static [&'static str]),
    /// The prescribed speed of every pulley.
    AllOmegaRef,
    /// The prescribed speeds of pulley 1 and of its own slot.
    FirstAndOwn,
    /// The prescribed speeds of pulley 1, its own slot and the next slot
    /// (a span from pulley k to the next pulley of the loop).
    Span,
}

/// One variable (one per slot if its name holds `#`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decl {
    /// Name; `#` stands for the 1-based slot.
    pub name: &'static str,
    /// Value reference(s).
    pub vr: Vr,
    /// Description; `{j}` stands for the slot.
    pub description: &'static str,
    /// `causality`.
    pub causality: &'static str,
    /// `variability`.
    pub variability: &'static str,
    /// `initial`, if written.
    pub initial: Option<&'static str>,
    /// Type.
    pub ty: Ty,
    /// Start value as written, per slot; the last one holds for the
    /// remaining slots (empty: no start value).
    pub start: &'static [&'static str],
    /// Lower bound as written.
    pub min: Option<&'static str>,
    /// Upper bound as written.
    pub max: Option<&'static str>,
    /// The lower bound itself is outside the range (a radius > 0).
    pub min_exclusive: bool,
    /// The upper bound itself is outside the range.
    pub max_exclusive: bool,
    /// Inputs an output depends on.
    pub deps: Deps,
    /// A parameter of the core: its id (a variant of `Param`; a pulley
    /// parameter's carries the 0-based slot) and the name a mechanical
    /// engineer knows it by (`Param`'s `Display`, a Rust user's messages).
    pub param: Option<(&'static str, &'static str)>,
    /// A coded Integer: each code and the core's value it stands for.
    pub codes: &'static [(i32, &'static str)],
}

const fn decl(
    name: &'static str,
    vr: Vr,
    ty: Ty,
    causality: &'static str,
    variability: &'static str,
    initial: Option<&'static str>,
    start: &'static [&'static str],
) -> Decl {
    Decl {
        name,
        vr,
        description: "",
        causality,
        variability,
        initial,
        ty,
        start,
        min: None,
        max: None,
        min_exclusive: false,
        max_exclusive: false,
        deps: Deps::None,
        param: None,
        codes: &[],
    }
}

/// A parameter (fixed, initial exact) with its start value(s).
pub const fn param(name: &'static str, vr: Vr, ty: Ty, start: &'static [&'static str]) -> Decl {
    decl(name, vr, ty, "parameter", "fixed", Some("exact"), start)
}

/// A continuous input with its start value(s).
pub const fn input(name: &'static str, vr: Vr, ty: Ty, start: &'static [&'static str]) -> Decl {
    decl(name, vr, ty, "input", "continuous", None, start)
}

/// A continuous output.
pub const fn output(name: &'static str, vr: Vr, ty: Ty) -> Decl {
    decl(name, vr, ty, "output", "continuous", None, &[])
}

/// A discrete output (a counter).
pub const fn discrete_output(name: &'static str, vr: Vr, ty: Ty) -> Decl {
    decl(name, vr, ty, "output", "discrete", None, &[])
}

/// A calculated parameter (found at initialization).
pub const fn calculated(name: &'static str, vr: Vr, ty: Ty) -> Decl {
    decl(
        name,
        vr,
        ty,
        "calculatedParameter",
        "fixed",
        Some("calculated"),
        &[],
    )
}

impl Decl {
    /// Closed lower bound.
    pub const fn min(mut self, min: &'static str) -> Self {
        self.min = Some(min);
        self
    }
    /// Open lower bound: the value must lie above it.
    pub const fn above(mut self, min: &'static str) -> Self {
        self.min = Some(min);
        self.min_exclusive = true;
        self
    }
    /// Closed upper bound.
    pub const fn max(mut self, max: &'static str) -> Self {
        self.max = Some(max);
        self
    }
    /// Open upper bound: the value must lie below it.
    pub const fn below(mut self, max: &'static str) -> Self {
        self.max = Some(max);
        self.max_exclusive = true;
        self
    }
    /// The inputs an output depends on.
    pub const fn deps(mut self, deps: Deps) -> Self {
        self.deps = deps;
        self
    }
    /// The core's parameter id and engineering name.
    pub const fn id(mut self, id: &'static str, label: &'static str) -> Self {
        self.param = Some((id, label));
        self
    }
    /// The codes of a coded Integer.
    pub const fn codes(mut self, codes: &'static [(i32, &'static str)]) -> Self {
        self.codes = codes;
        self
    }
    /// The description.
    pub const fn about(mut self, description: &'static str) -> Self {
        self.description = description;
        self
    }

    /// Whether the declaration stands for one variable per slot.
    pub fn slotted(&self) -> bool {
        self.name.contains('#')
    }

    /// Name in slot `j`.
    pub fn name_in(&self, j: usize) -> String {
        self.name.replace('#', &j.to_string())
    }

    /// Start value as written in slot `j` (1-based).
    pub fn start_in(&self, j: usize) -> Option<&'static str> {
        let s = self.start;
        s.get(j.saturating_sub(1)).or(s.last()).copied()
    }
}

/// One entry of the registry, in the order of the model description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Item {
    /// A comment line.
    Comment(&'static str),
    /// A variable without slots.
    One(Decl),
    /// Pulley variables written slot by slot (all of slot 1, then slot 2,
    /// ...), each slot under the comment (`{j}`: the slot), if any.
    Slots(Option<&'static str>, &'static [Decl]),
    /// One variable over the slots (`span[1].tension` ... `span[n].tension`).
    Array(Decl),
}

/// Every variable in model-description order: (declaration, slot; 0 for
/// none), with the comments before it.
fn expanded() -> Vec<(Vec<String>, Decl, usize)> {
    let mut out = Vec::new();
    let mut comments = Vec::new();
    for item in REGISTRY {
        match *item {
            Item::Comment(c) => comments.push(c.to_owned()),
            Item::One(d) => out.push((std::mem::take(&mut comments), d, 0)),
            Item::Array(d) => {
                for j in 1..=SLOTS {
                    out.push((std::mem::take(&mut comments), d, j));
                }
            }
            Item::Slots(comment, decls) => {
                for j in 1..=SLOTS {
                    if let Some(c) = comment {
                        comments.push(c.replace("{j}", &j.to_string()));
                    }
                    for d in decls {
                        out.push((std::mem::take(&mut comments), *d, j));
                    }
                }
            }
        }
    }
    out
}

/// Every declaration, once (in registry order).
pub fn declarations() -> impl Iterator<Item = &'static Decl> {
    REGISTRY.iter().flat_map(|item| match item {
        Item::Comment(_) => &[][..],
        Item::One(d) | Item::Array(d) => std::slice::from_ref(d),
        Item::Slots(_, decls) => decls,
    })
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('"', "&quot;")
}

const HEADER: &str = include_str!("header.xml");

/// The text of `modelDescription.xml`.
pub fn model_description() -> String {
    let vars = expanded();
    let mut bounds = String::new();
    let mut order: Vec<&(Vec<String>, Decl, usize)> =
        vars.iter().filter(|(_, d, _)| !d.slotted()).collect();
    for j in 1..=SLOTS {
        order.extend(vars.iter().filter(|(_, d, s)| d.slotted() && *s == j));
    }
    for (_, d, j) in order {
        if d.min_exclusive || d.max_exclusive {
            let _ = write!(bounds, "        <Range variable=\"{}\"", d.name_in(*j));
            if d.min_exclusive {
                bounds.push_str(" min=\"exclusive\"");
            }
            if d.max_exclusive {
                bounds.push_str(" max=\"exclusive\"");
            }
            bounds.push_str("/>\n");
        }
    }
    let mut o = HEADER
        .replace("@SLOTS@", &SLOTS.to_string())
        .replace("@EXCLUSIVE_BOUNDS@\n", &bounds);
    o.push_str("  <ModelVariables>\n");
    let mut index = std::collections::HashMap::new();
    for (i, (_, d, j)) in vars.iter().enumerate() {
        index.insert(d.name_in(*j), i + 1);
    }
    for (i, (comments, d, j)) in vars.iter().enumerate() {
        for c in comments {
            let _ = writeln!(o, "    <!-- {c} -->");
        }
        let desc = d
            .description
            .replace("{j}", &j.to_string())
            .replace("@SLOTS@", &SLOTS.to_string());
        let _ = write!(
            o,
            "    <!-- index {} --><ScalarVariable name=\"{}\" valueReference=\"{}\" description=\"{}\" causality=\"{}\" variability=\"{}\"",
            i + 1,
            d.name_in(*j),
            d.vr.of(*j),
            escape(&desc),
            d.causality,
            d.variability
        );
        if let Some(init) = d.initial {
            let _ = write!(o, " initial=\"{init}\"");
        }
        o.push_str(">\n      <");
        match d.ty {
            Ty::Real(t) => {
                let _ = write!(o, "Real declaredType=\"{t}\"");
            }
            Ty::Integer => o.push_str("Integer"),
            Ty::Boolean => o.push_str("Boolean"),
        }
        for (key, value) in [("start", d.start_in(*j)), ("min", d.min), ("max", d.max)] {
            if let Some(v) = value {
                let v = v.replace("@SLOTS@", &SLOTS.to_string());
                let _ = write!(o, " {key}=\"{v}\"");
            }
        }
        o.push_str("/>\n    </ScalarVariable>\n");
    }
    o.push_str("  </ModelVariables>\n\n  <ModelStructure>\n    <Outputs>\n");
    let omega_ref = |k: usize| index[&format!("pulley[{k}].omegaRef")];
    for (i, (_, d, j)) in vars.iter().enumerate() {
        if d.causality != "output" {
            continue;
        }
        let mut deps: Vec<usize> = match d.deps {
            Deps::None => Vec::new(),
            Deps::Own(names) => names
                .iter()
                .map(|n| index[&format!("pulley[{j}].{n}")])
                .collect(),
            Deps::AllOmegaRef => (1..=SLOTS).map(omega_ref).collect(),
            Deps::FirstAndOwn => vec![omega_ref(1), omega_ref(*j)],
            Deps::Span => {
                let mut v = vec![omega_ref(1), omega_ref(*j)];
                if *j < SLOTS {
                    v.push(omega_ref(j + 1));
                }
                v
            }
        };
        deps.sort_unstable();
        deps.dedup();
        let list: Vec<String> = deps.iter().map(usize::to_string).collect();
        let _ = writeln!(
            o,
            "      <Unknown index=\"{}\" dependencies=\"{}\"/>",
            i + 1,
            list.join(" ")
        );
    }
    o.push_str("    </Outputs>\n    <InitialUnknowns>\n");
    for (i, (_, d, _)) in vars.iter().enumerate() {
        if d.causality == "output" || d.causality == "calculatedParameter" {
            let _ = writeln!(o, "      <Unknown index=\"{}\"/>", i + 1);
        }
    }
    o.push_str("    </InitialUnknowns>\n  </ModelStructure>\n\n</fmiModelDescription>\n");
    o
}

/// The core's parameter ids with their variables (`#`: the slot), in
/// registry order.
pub fn param_ids() -> Vec<(&'static str, &'static str)> {
    declarations()
        .filter_map(|d| d.param.map(|(id, _)| (id, d.name)))
        .collect()
}

/// The coded Integer parameters: id and codes.
pub fn param_codes() -> Vec<(&'static str, &'static [(i32, &'static str)])> {
    declarations()
        .filter(|d| !d.codes.is_empty())
        .filter_map(|d| d.param.map(|(id, _)| (id, d.codes)))
        .collect()
}

/// The `params!` invocation that defines the core's `Param`: the drive's
/// parameters (`Id => "engineering name",`), then the pulleys'.
pub fn param_list() -> String {
    let mut drive = String::new();
    let mut pulley = String::new();
    for d in declarations() {
        if let Some((id, label)) = d.param {
            let list = if d.slotted() { &mut pulley } else { &mut drive };
            let _ = writeln!(list, "        {id} => {label:?},");
        }
    }
    format!(
        "// @generated by the model_description crate from its registry. Do not edit.\n\
         params! {{\n    drive {{\n{drive}    }}\n    pulley {{\n{pulley}    }}\n}}\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The model description in the repository is the registry's: edit
    /// `modelDescription/src/registry/table.rs`, then run
    /// `cargo xtask model-description`.
    #[test]
    fn checked_in_model_description_is_generated() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription.xml");
        let file = std::fs::read_to_string(path).unwrap();
        let generated = model_description();
        if file != generated {
            let line = file
                .lines()
                .zip(generated.lines())
                .position(|(a, b)| a != b)
                .map_or(0, |i| i + 1);
            panic!("modelDescription.xml differs from the registry from line {line}: run `cargo xtask model-description`");
        }
        crate::compile(&generated).unwrap();
    }

    #[test]
    fn value_references() {
        assert_eq!(Vr::Pulley(3).of(2), 203);
        assert_eq!(Vr::PulleyOutput(4).of(6), 1604);
        assert_eq!(Vr::PulleyOutput(4).of(7), 10704);
        assert_eq!(Vr::Array(1740).of(3), 1743);
    }
}
