//! A model's identity and variable table as the plumbing sees it: what the
//! model description says about each variable, and the look-ups by value
//! reference and by name. A model's table is generated from its
//! `modelDescription.xml` (see the `model_description` crate) and handed to
//! the plumbing by [`crate::fmi::FmuModel::description`].

/// FMI 2.0 base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarType {
    /// FMI `Real` (f64).
    Real,
    /// FMI `Integer` (i32).
    Integer,
    /// FMI `Boolean`.
    Boolean,
    /// FMI `String`.
    String,
}

/// FMI 2.0 `causality`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// `parameter`: set by the importer before or during initialization (tunable ones also later).
    Parameter,
    /// `calculatedParameter`: computed from parameters.
    CalculatedParameter,
    /// `input`: set by the importer at any communication point.
    Input,
    /// `output`: computed by the model.
    Output,
    /// `local`: internal.
    Local,
    /// `independent`: the time.
    Independent,
}

/// FMI 2.0 `variability`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// `constant`: never changes.
    Constant,
    /// `fixed`: fixed after initialization.
    Fixed,
    /// `tunable`: may change at communication points.
    Tunable,
    /// `discrete`: changes at events only.
    Discrete,
    /// `continuous`: changes continuously (Real only).
    Continuous,
}

/// The `start` attribute (`None` for calculated variables).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// No start value (`initial="calculated"`).
    None,
    /// Start of a Real variable.
    Real(f64),
    /// Start of an Integer variable.
    Integer(i32),
    /// Start of a Boolean variable.
    Boolean(bool),
    /// Start of a String variable.
    String(&'static str),
}

/// One ScalarVariable of a model description. `K` is the model's own key
/// for it (for generated tables: one enum variant per base name).
#[derive(Clone, Copy, Debug)]
pub struct VarInfo<K: 'static> {
    /// Value reference (unique across all types).
    pub vr: u32,
    /// Full name, e.g. `wheel[2].force.x`.
    pub name: &'static str,
    /// The model's key, e.g. `Var::WheelForceX` (one per base name).
    pub var: K,
    /// 0-based array index (`wheel[2]` -> 1); 0 for scalars.
    pub index: usize,
    /// Base type (the element inside `<ScalarVariable>`).
    pub ty: VarType,
    /// `causality`.
    pub causality: Causality,
    /// `variability`.
    pub variability: Variability,
    /// `start`.
    pub start: Start,
    /// `min` of a Real or Integer variable (`None`: unbounded).
    pub min: Option<f64>,
    /// `max` of a Real or Integer variable (`None`: unbounded).
    pub max: Option<f64>,
    /// `description`.
    pub description: &'static str,
    /// Unit (own or from the declared type); empty if dimensionless.
    pub unit: &'static str,
}

impl<K> VarInfo<K> {
    /// `Err` naming the variable and its range if `x` is outside
    /// `[min, max]` (NaN is outside every declared range).
    pub fn check_range(&self, x: f64) -> Result<(), String> {
        let below = self.min.is_some_and(|lo| x.is_nan() || x < lo);
        let above = self.max.is_some_and(|hi| x.is_nan() || x > hi);
        if !(below || above) {
            return Ok(());
        }
        let range = match (self.min, self.max) {
            (Some(lo), Some(hi)) => format!("in {lo}..={hi}"),
            (Some(lo), None) => format!(">= {lo}"),
            (None, Some(hi)) => format!("<= {hi}"),
            (None, None) => unreachable!("a value outside no bounds"),
        };
        Err(format!("{} must be {range} (got {x})", self.name))
    }
}

/// A model's identity and variables: everything the plumbing needs to know
/// about a model besides its behaviour ([`crate::fmi::FmuModel`]).
#[derive(Debug)]
pub struct ModelDescription<K: 'static> {
    /// `modelIdentifier` (the binary's name).
    pub model_identifier: &'static str,
    /// The GUID fmi2Instantiate must be given; also stamped into serialized
    /// FMU states.
    pub guid: &'static str,
    /// `<LogCategories>` in XML order; must include the plumbing's own
    /// ([`crate::fmi::logging::PLUMBING_CATEGORIES`]).
    pub log_categories: &'static [&'static str],
    /// Every ScalarVariable in XML order.
    pub variables: &'static [VarInfo<K>],
    /// (value reference, position in `variables`), sorted by value reference.
    pub by_vr: &'static [(u32, u32)],
    /// (name, position in `variables`), sorted by name (byte order).
    pub by_name: &'static [(&'static str, u32)],
}

impl<K> ModelDescription<K> {
    /// The variable with value reference `vr`, whatever its type.
    pub fn by_vr(&self, vr: u32) -> Option<&'static VarInfo<K>> {
        let i = self.by_vr.binary_search_by_key(&vr, |&(r, _)| r).ok()?;
        self.variables.get(self.by_vr[i].1 as usize)
    }

    /// The variable of type `ty` with value reference `vr`.
    pub fn lookup(&self, ty: VarType, vr: u32) -> Option<&'static VarInfo<K>> {
        self.by_vr(vr).filter(|v| v.ty == ty)
    }

    /// The variable with this exact name.
    pub fn by_name(&self, name: &str) -> Option<&'static VarInfo<K>> {
        let i = self.by_name.binary_search_by(|&(n, _)| n.cmp(name)).ok()?;
        self.variables.get(self.by_name[i].1 as usize)
    }

    /// Whether the two indices are sorted and name every variable exactly
    /// once (what the look-ups rely on).
    pub fn validate(&self) -> Result<(), String> {
        let n = self.variables.len();
        if self.by_vr.len() != n || self.by_name.len() != n {
            return Err(format!(
                "{n} variables but {} value-reference and {} name index entries",
                self.by_vr.len(),
                self.by_name.len()
            ));
        }
        for w in self.by_vr.windows(2) {
            if w[0].0 >= w[1].0 {
                return Err(format!("value references not ascending at {}", w[1].0));
            }
        }
        for w in self.by_name.windows(2) {
            if w[0].0 >= w[1].0 {
                return Err(format!("names not ascending at {}", w[1].0));
            }
        }
        for &(vr, i) in self.by_vr {
            if self.variables.get(i as usize).map(|v| v.vr) != Some(vr) {
                return Err(format!("value reference {vr} indexes the wrong variable"));
            }
        }
        for &(name, i) in self.by_name {
            if self.variables.get(i as usize).map(|v| v.name) != Some(name) {
                return Err(format!("name {name} indexes the wrong variable"));
            }
        }
        Ok(())
    }
}
