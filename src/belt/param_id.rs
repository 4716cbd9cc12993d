//! Parameter ids: how the core names a parameter in its errors and
//! warnings. The core knows no variable names of the FMU; the FMU layer
//! (`crate::fmu`) turns an id into its variable's name from the table
//! generated from the model description. A message is text with ids (and
//! pulley references) in it, so that each layer can spell
//! them its own way.

/// A parameter of the drive. Pulley parameters carry the pulley's index
/// (0-based, in the listed belt order).
#[allow(missing_docs)] // each variant is the parameter of the same name in `DriveParams`
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Param {
    /// Number of pulleys (the length of `DriveParams::pulleys`).
    PulleyCount,
    BeltBodies,
    BeltPreload,
    BeltEa,
    BeltAxialDamping,
    BeltBendingStiffness,
    BeltBendingDamping,
    BeltMassPerLength,
    ContactC1,
    ContactC2,
    ContactDamping,
    ContactPMax,
    FrictionLaw,
    FrictionDv,
    FrictionCreepMax,
    FrictionCreepDampingTime,
    FrictionZoneFactor,
    FrictionZoneStart,
    FrictionZoneBodies,
    Gravity,
    ProbeBody,
    SolverMethod,
    SolverRelTol,
    SolverAbsTol,
    SolverInitialStep,
    SolverMaxSteps,
    PulleyX(usize),
    PulleyY(usize),
    PulleyRadius(usize),
    PulleyInertia(usize),
    PulleyMuStatic(usize),
    PulleyMuKinetic(usize),
    PulleyLoadDamping(usize),
    PulleyTorqueRamp(usize),
    PulleyOmegaRamp(usize),
    PulleyRampTime(usize),
    PulleyGrooveAngle(usize),
    PulleyBackSide(usize),
    PulleyDecoupler(usize),
    PulleyDecouplerStiffness(usize),
    PulleyDecouplerDamping(usize),
    PulleyRotorInertia(usize),
    PulleyTensioner(usize),
    PulleyArmPivotX(usize),
    PulleyArmPivotY(usize),
    PulleyArmInertia(usize),
    PulleyArmStiffness(usize),
    PulleyArmDamping(usize),
    PulleyArmFriction(usize),
}

impl std::fmt::Display for Param {
    /// The parameter as a mechanical engineer names it (the FMU layer uses
    /// its variable names instead).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use Param::*;
        let pulley = |f: &mut std::fmt::Formatter<'_>, j: &usize, what: &str| {
            write!(f, "pulley {} {what}", j + 1)
        };
        match self {
            PulleyCount => f.write_str("number of pulleys"),
            BeltBodies => f.write_str("number of belt bodies"),
            BeltPreload => f.write_str("belt preload"),
            BeltEa => f.write_str("belt axial stiffness EA"),
            BeltAxialDamping => f.write_str("belt axial damping"),
            BeltBendingStiffness => f.write_str("belt bending stiffness"),
            BeltBendingDamping => f.write_str("belt bending damping"),
            BeltMassPerLength => f.write_str("belt mass per length"),
            ContactC1 => f.write_str("contact stiffness c1"),
            ContactC2 => f.write_str("contact stiffness c2"),
            ContactDamping => f.write_str("contact damping"),
            ContactPMax => f.write_str("contact damping ramp p_max"),
            FrictionLaw => f.write_str("friction law"),
            FrictionDv => f.write_str("friction transition velocity dv"),
            FrictionCreepMax => f.write_str("friction creep displacement max"),
            FrictionCreepDampingTime => f.write_str("friction creep damping time"),
            FrictionZoneFactor => f.write_str("friction zone factor"),
            FrictionZoneStart => f.write_str("friction zone start body"),
            FrictionZoneBodies => f.write_str("friction zone bodies"),
            Gravity => f.write_str("gravity"),
            ProbeBody => f.write_str("probe body"),
            SolverMethod => f.write_str("integrator"),
            SolverRelTol => f.write_str("relative tolerance"),
            SolverAbsTol => f.write_str("absolute tolerance"),
            SolverInitialStep => f.write_str("initial step"),
            SolverMaxSteps => f.write_str("step-count guard"),
            PulleyX(j) => pulley(f, j, "centre x"),
            PulleyY(j) => pulley(f, j, "centre y"),
            PulleyRadius(j) => pulley(f, j, "radius"),
            PulleyInertia(j) => pulley(f, j, "inertia"),
            PulleyMuStatic(j) => pulley(f, j, "static friction coefficient"),
            PulleyMuKinetic(j) => pulley(f, j, "kinetic friction coefficient"),
            PulleyLoadDamping(j) => pulley(f, j, "load damping"),
            PulleyTorqueRamp(j) => pulley(f, j, "torque ramp"),
            PulleyOmegaRamp(j) => pulley(f, j, "speed ramp"),
            PulleyRampTime(j) => pulley(f, j, "ramp time"),
            PulleyGrooveAngle(j) => pulley(f, j, "groove angle"),
            PulleyBackSide(j) => pulley(f, j, "back side"),
            PulleyDecoupler(j) => pulley(f, j, "decoupler"),
            PulleyDecouplerStiffness(j) => pulley(f, j, "decoupler stiffness"),
            PulleyDecouplerDamping(j) => pulley(f, j, "decoupler damping"),
            PulleyRotorInertia(j) => pulley(f, j, "rotor inertia"),
            PulleyTensioner(j) => pulley(f, j, "tensioner"),
            PulleyArmPivotX(j) => pulley(f, j, "tensioner pivot x"),
            PulleyArmPivotY(j) => pulley(f, j, "tensioner pivot y"),
            PulleyArmInertia(j) => pulley(f, j, "tensioner arm inertia"),
            PulleyArmStiffness(j) => pulley(f, j, "tensioner spring stiffness"),
            PulleyArmDamping(j) => pulley(f, j, "tensioner arm damping"),
            PulleyArmFriction(j) => pulley(f, j, "tensioner pivot friction"),
        }
    }
}

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
