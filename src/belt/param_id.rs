//! Parameter ids: how the core names a parameter in its errors and
//! warnings. The core knows no variable names of the FMU; the FMU layer
//! (`crate::fmu`) turns an id into its variable's name from the table
//! generated from the model description. A message is text with ids (and
//! pulley references) in it, so that each layer can spell
//! them its own way.

/// Defines [`Param`] from one list: each variant with the name a mechanical
/// engineer knows it by (its `Display` and doc), the drive's parameters
/// first, then each pulley's (which carry the pulley's 0-based index).
macro_rules! params {
    (
        drive { $($d:ident => $dname:literal,)* }
        pulley { $($p:ident => $pname:literal,)* }
    ) => {
        /// A parameter of the drive. Pulley parameters carry the pulley's
        /// index (0-based, in the listed belt order). Its range:
        /// [`Param::declared`].
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Param {
            $(#[doc = $dname] $d,)*
            $(#[doc = concat!("pulley ", $pname)] $p(usize),)*
        }

        impl Param {
            /// Every parameter id: the drive's, then those of `pulleys`
            /// pulleys, pulley by pulley.
            pub fn all(pulleys: usize) -> impl Iterator<Item = Param> {
                [$(Param::$d),*]
                    .into_iter()
                    .chain((0..pulleys).flat_map(|j| [$(Param::$p(j)),*]))
            }
        }

        impl std::fmt::Display for Param {
            /// The parameter as a mechanical engineer names it (the FMU
            /// layer uses its variable names instead).
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                match self {
                    $(Param::$d => f.write_str($dname),)*
                    $(Param::$p(j) => write!(f, "pulley {} {}", j + 1, $pname),)*
                }
            }
        }
    };
}

params! {
    drive {
        PulleyCount => "number of pulleys",
        BeltBodies => "number of belt bodies",
        BeltPreload => "belt preload",
        BeltEa => "belt axial stiffness EA",
        BeltAxialDamping => "belt axial damping",
        BeltShearDampingFactor => "belt shear damping factor",
        BeltBendingStiffness => "belt bending stiffness",
        BeltBendingDamping => "belt bending damping",
        BeltMassPerLength => "belt mass per length",
        ContactC1 => "contact stiffness c1",
        ContactC2 => "contact stiffness c2",
        ContactDamping => "contact damping",
        ContactPMax => "contact damping ramp p_max",
        ContactPoints => "contact points per body",
        FrictionLaw => "friction law",
        FrictionDv => "friction transition velocity dv",
        FrictionCreepMax => "friction creep displacement max",
        FrictionCreepDampingTime => "friction creep damping time",
        FrictionZoneFactor => "friction zone factor",
        FrictionZoneStart => "friction zone start body",
        FrictionZoneBodies => "friction zone bodies",
        Gravity => "gravity",
        ProbeBody => "probe body",
        SolverMethod => "integrator",
        SolverRelTol => "relative tolerance",
        SolverAbsTol => "absolute tolerance",
        SolverInitialStep => "initial step",
        SolverMaxSteps => "step-count guard",
    }
    pulley {
        PulleyX => "centre x",
        PulleyY => "centre y",
        PulleyRadius => "radius",
        PulleyInertia => "inertia",
        PulleyMuStatic => "static friction coefficient",
        PulleyMuKinetic => "kinetic friction coefficient",
        PulleyLoadDamping => "load damping",
        PulleyTorqueRamp => "torque ramp",
        PulleyOmegaRamp => "speed ramp",
        PulleyRampTime => "ramp time",
        PulleySpeedDriven => "speed driven",
        PulleyGrooveAngle => "groove angle",
        PulleyBackSide => "back side",
        PulleyDecoupler => "decoupler",
        PulleyDecouplerClockwise => "decoupler driving clockwise",
        PulleyDecouplerStiffness => "decoupler stiffness",
        PulleyDecouplerDamping => "decoupler damping",
        PulleyRotorInertia => "rotor inertia",
        PulleyTensioner => "tensioner",
        PulleyArmPivotX => "tensioner pivot x",
        PulleyArmPivotY => "tensioner pivot y",
        PulleyArmInertia => "tensioner arm inertia",
        PulleyArmStiffness => "tensioner spring stiffness",
        PulleyArmDamping => "tensioner arm damping",
        PulleyArmFriction => "tensioner pivot friction",
    }
}

/// A parameter's declared range and unit, as the model description states
/// them (generated: [`Param::declared`]). FMI's `min` and `max` are
/// inclusive; an end marked exclusive (the model description's range
/// annotation) is the limit the value must pass, e.g. a radius > 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeclaredRange {
    /// Lower bound (`None`: unbounded).
    pub min: Option<f64>,
    /// Upper bound (`None`: unbounded).
    pub max: Option<f64>,
    /// `min` itself is outside the range.
    pub min_exclusive: bool,
    /// `max` itself is outside the range.
    pub max_exclusive: bool,
    /// SI unit (empty: dimensionless or none).
    pub unit: &'static str,
}

impl DeclaredRange {
    /// Whether `x` is finite and inside the range.
    pub fn contains(&self, x: f64) -> bool {
        let above_min = self
            .min
            .is_none_or(|lo| x > lo || (!self.min_exclusive && x == lo));
        let below_max = self
            .max
            .is_none_or(|hi| x < hi || (!self.max_exclusive && x == hi));
        x.is_finite() && above_min && below_max
    }

    /// The range as a refusal states it: `finite and > 0 m`,
    /// `finite and in [0, 1] s`, `finite` (no bounds).
    pub fn describe(&self) -> String {
        let unit = match self.unit {
            "" | "1" => String::new(),
            u => format!(" {u}"),
        };
        let range = match (self.min, self.max) {
            (None, None) => return "finite".into(),
            (Some(lo), None) => format!("{} {lo}", if self.min_exclusive { ">" } else { ">=" }),
            (None, Some(hi)) => format!("{} {hi}", if self.max_exclusive { "<" } else { "<=" }),
            (Some(lo), Some(hi)) => format!(
                "in {}{lo}, {hi}{}",
                if self.min_exclusive { "(" } else { "[" },
                if self.max_exclusive { ")" } else { "]" }
            ),
        };
        format!("finite and {range}{unit}")
    }
}

// `impl Param { pub const fn declared(self) -> DeclaredRange }`, generated
// by build.rs from the model description.
include!(concat!(env!("OUT_DIR"), "/param_ranges.rs"));

/// One piece of a [`Message`].
#[derive(Clone, Debug, PartialEq)]
pub enum Part {
    /// Plain text.
    Text(String),
    /// A parameter's name.
    Param(Param),
    /// A pulley (0-based index).
    Pulley(usize),
}

impl From<&str> for Part {
    fn from(s: &str) -> Self {
        Self::Text(s.to_owned())
    }
}

impl From<String> for Part {
    fn from(s: String) -> Self {
        Self::Text(s)
    }
}

impl From<Param> for Part {
    fn from(p: Param) -> Self {
        Self::Param(p)
    }
}

/// A message of the core: text with parameters and pulleys in it, spelt by whoever shows it ([`Message::render`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Message(pub Vec<Part>);

/// Builds a [`Message`] from pieces that convert into [`Part`].
macro_rules! msg {
    ($($part:expr),* $(,)?) => {
        $crate::belt::param_id::Message(vec![$($crate::belt::param_id::Part::from($part)),*])
    };
}
pub(crate) use msg;

/// How a layer spells the references in a message.
pub trait Spelling {
    /// A parameter's name.
    fn param(&self, p: Param) -> String;
    /// A pulley's name (0-based index).
    fn pulley(&self, j: usize) -> String;
}

/// The core's own spelling (engineering names, for Rust users).
pub struct Plain;

impl Spelling for Plain {
    fn param(&self, p: Param) -> String {
        p.to_string()
    }
    fn pulley(&self, j: usize) -> String {
        format!("pulley {}", j + 1)
    }
}

impl Message {
    /// The message as text, with its references spelt by `s`.
    pub fn render(&self, s: &dyn Spelling) -> String {
        let mut out = String::new();
        for part in &self.0 {
            match part {
                Part::Text(t) => out.push_str(t),
                Part::Param(p) => out.push_str(&s.param(*p)),
                Part::Pulley(j) => out.push_str(&s.pulley(*j)),
            }
        }
        out
    }
}

impl std::fmt::Display for Message {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render(&Plain))
    }
}
