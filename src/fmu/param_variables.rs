// The variable of each parameter id of the core (`crate::belt::param_id::Param`):
// (id, variable name), `#` standing for the 1-based pulley slot of a pulley
// parameter (`PulleyRadius(j)` is `pulley[j + 1].radius`).
//
// Not a module: `build.rs` includes this list and generates from it and
// `modelDescription/modelDescription.xml`
// * `Param::declared()` for the core: each id's range and unit (numbers only,
//   so the core learns no variable names);
// * `Param::start()` for the core: each id's start value, the defaults of
//   `DriveParams::default()` (and the `START_*` constants: the start values of
//   the coded parameters below, decoded);
// * `var_of` for `src/fmu/names.rs`: each id's variable, and the decoding of
//   the codes below.
// The `match`es have no wildcard: a `Param` missing here does not compile.

const PARAM_VARIABLES: &[(&str, &str)] = &[
    ("PulleyCount", "nPulleys"),
    ("BeltBodies", "belt.nBodies"),
    ("BeltPreload", "belt.preload"),
    ("BeltEa", "belt.EA"),
    ("BeltAxialDamping", "belt.axialDamping"),
    ("BeltShearDampingFactor", "belt.shearDampingFactor"),
    ("BeltBendingStiffness", "belt.bendingStiffness"),
    ("BeltBendingDamping", "belt.bendingDamping"),
    ("BeltMassPerLength", "belt.massPerLength"),
    ("ContactC1", "contact.c1"),
    ("ContactC2", "contact.c2"),
    ("ContactDamping", "contact.damping"),
    ("ContactPMax", "contact.pMax"),
    ("ContactPoints", "contact.points"),
    ("FrictionLaw", "friction.law"),
    ("FrictionDv", "friction.dv"),
    ("FrictionCreepMax", "friction.creepMax"),
    ("FrictionCreepDampingTime", "friction.creepDampingTime"),
    ("FrictionZoneFactor", "friction.zoneFactor"),
    ("FrictionZoneStart", "friction.zoneStart"),
    ("FrictionZoneBodies", "friction.zoneBodies"),
    ("Gravity", "gravity"),
    ("ProbeBody", "probe.body"),
    ("SolverMethod", "solver.method"),
    ("SolverRelTol", "solver.relTol"),
    ("SolverAbsTol", "solver.absTol"),
    ("SolverInitialStep", "solver.initialStep"),
    ("SolverMaxSteps", "solver.maxSteps"),
    ("PulleyX", "pulley[#].x"),
    ("PulleyY", "pulley[#].y"),
    ("PulleyRadius", "pulley[#].radius"),
    ("PulleyInertia", "pulley[#].inertia"),
    ("PulleyMuStatic", "pulley[#].muStatic"),
    ("PulleyMuKinetic", "pulley[#].muKinetic"),
    ("PulleyLoadDamping", "pulley[#].loadDamping"),
    ("PulleyTorqueRamp", "pulley[#].torqueRamp"),
    ("PulleyOmegaRamp", "pulley[#].omegaRamp"),
    ("PulleyRampTime", "pulley[#].rampTime"),
    ("PulleySpeedDriven", "pulley[#].speedDriven"),
    ("PulleyGrooveAngle", "pulley[#].grooveAngle"),
    ("PulleyBackSide", "pulley[#].backSide"),
    ("PulleyDecoupler", "pulley[#].decoupler"),
    ("PulleyDecouplerClockwise", "pulley[#].decoupler.clockwise"),
    ("PulleyDecouplerStiffness", "pulley[#].decoupler.stiffness"),
    ("PulleyDecouplerDamping", "pulley[#].decoupler.damping"),
    ("PulleyRotorInertia", "pulley[#].rotor.inertia"),
    ("PulleyTensioner", "pulley[#].tensioner"),
    ("PulleyArmPivotX", "pulley[#].arm.pivot.x"),
    ("PulleyArmPivotY", "pulley[#].arm.pivot.y"),
    ("PulleyArmInertia", "pulley[#].arm.inertia"),
    ("PulleyArmStiffness", "pulley[#].arm.stiffness"),
    ("PulleyArmDamping", "pulley[#].arm.damping"),
    ("PulleyArmFriction", "pulley[#].arm.friction"),
];

// The Integer parameters whose values are codes: each code and the core's
// value it stands for (paths as `src/belt/params.rs` and `src/fmu/names.rs`
// name them). The core knows the values, only this list the codes.
const PARAM_CODES: &[(&str, &[(i32, &str)])] = &[
    (
        "FrictionLaw",
        &[(1, "FrictionLaw::Kubas2014"), (2, "FrictionLaw::Creep")],
    ),
    ("SolverMethod", &[(1, "Method::Rkf45"), (2, "Method::Rosenbrock")]),
];
