//! The registry's table: every variable of the FMU, declared once, in the
//! order of the model description (see the module above for what is
//! generated from it). A pulley variable's `#` stands for the slot
//! (1..=[`SLOTS`]); its start values are listed per slot, the last one
//! holding for the remaining slots; `{j}` in a description is the slot.
//!
//! To add a parameter: one declaration here (name, value reference, type,
//! start, range, `.id(...)` for the core, description), then `cargo xtask
//! model-description` to write `modelDescription.xml`; the core's `Param`
//! gains the id, its range, start value and name, and the adapter its
//! variable.

use super::{calculated, discrete_output, input, output, param, Deps, Item, Ty, Vr};

/// The number of pulley slots: every pulley variable exists this many times.
pub const SLOTS: usize = 8;

/// Every variable, in model-description order.
pub static REGISTRY: &[Item] = &[
    Item::Comment("Integer parameters"),
    Item::One(param("nPulleys", Vr::Fixed(1), Ty::Integer, &["2"])
        .min("2")
        .max("@SLOTS@")
        .id("PulleyCount", "number of pulleys")
        .about("Number of pulleys used (1..@SLOTS@ is the slot range; at least 2 needed), listed in belt order around the loop")),
    Item::One(param("belt.nBodies", Vr::Fixed(2), Ty::Integer, &["150"])
        .min("3")
        .max("2000")
        .id("BeltBodies", "number of belt bodies")
        .about("Number of rigid bodies the belt is discretised into")),
    Item::One(param("friction.law", Vr::Fixed(3), Ty::Integer, &["2"])
        .min("1")
        .max("2")
        .id("FrictionLaw", "friction law")
        .codes(&[(1, "FrictionLaw::Kubas2014"), (2, "FrictionLaw::Creep")])
        .about("Friction law: 1 = kubas2014 (eq. 12-19, velocity-regularised), 2 = creep (elastic-plastic creep displacement)")),
    Item::One(param("friction.zoneStart", Vr::Fixed(4), Ty::Integer, &["1"])
        .min("1")
        .id("FrictionZoneStart", "friction zone start body")
        .about("First body (1-based) of the belt zone with modified friction (oil contamination)")),
    Item::One(param("friction.zoneBodies", Vr::Fixed(5), Ty::Integer, &["0"])
        .min("0")
        .id("FrictionZoneBodies", "friction zone bodies")
        .about("Number of bodies in the modified-friction zone (0 = none)")),
    Item::One(param("probe.body", Vr::Fixed(6), Ty::Integer, &["0"])
        .min("0")
        .id("ProbeBody", "probe body")
        .about("Belt body (1-based) whose forces are reported by the probe outputs (Figs. 15-18); 0 = chosen automatically: the body nearest the middle of the free span from pulley 1 to pulley 2 when mounted (logged at initialization)")),
    Item::One(param("solver.method", Vr::Fixed(7), Ty::Integer, &["1"])
        .min("1")
        .max("2")
        .id("SolverMethod", "integrator")
        .codes(&[(1, "Method::Rkf45"), (2, "Method::Rosenbrock")])
        .about("Integrator: 1 = RKF45 (Fehlberg 4(5), adaptive); 2 = Rosenbrock-W ROS34PW2 (linearly implicit, L-stable: 20-100x fewer steps, faster than real time on the default drive)")),
    Item::One(param("solver.maxSteps", Vr::Fixed(8), Ty::Integer, &["100000"])
        .min("1")
        .id("SolverMaxSteps", "step-count guard")
        .about("Step-count guard: integrator steps per millisecond of a communication step (a doStep over H may take maxSteps * max(1, H / 1 ms) steps, so a step of any length completes; the default stops a call whose mean step falls below 10 ns)")),
    Item::One(param("contact.points", Vr::Fixed(9), Ty::Integer, &["4"])
        .min("1")
        .max("5")
        .id("ContactPoints", "contact points per body")
        .about("Contact points along each belt body: the contact's penalty law per unit belt length integrated over the body's length by this many Gauss-Legendre points, each with its own penetration, sliding velocity and friction, acting at the point (1 = the body centre, the paper's contact, eq. 4-8)")),
    Item::Comment("Real parameters"),
    Item::One(param("belt.preload", Vr::Fixed(10), Ty::Real("Force"), &["550"])
        .min("0")
        .id("BeltPreload", "belt preload")
        .about("Belt preload (static tension at assembly)")),
    Item::One(param("belt.naturalLength", Vr::Fixed(30), Ty::Real("Length"), &["0"])
        .min("0")
        .id("BeltNaturalLength", "belt natural length")
        .about("Natural (unstretched) length of the belt at its pitch line, as the belt is specified; 0 (default) = the installation tension is belt.preload. When given, mounting finds the tension at which the belt of this length fits the drive (reported as belt.installedTension; belt.preload must then stay at its default). A catalogue's effective length L_e of a V-ribbed belt is converted to the pitch line by L_e + 2 pi h_b (docs/fmu-manual.md)")),
    Item::One(param("belt.EA", Vr::Fixed(11), Ty::Real("Force"), &["1.52e5"])
        .above("0")
        .id("BeltEa", "belt axial stiffness EA")
        .about("Axial stiffness EA of the belt (each SDE gets EA/l)")),
    Item::One(param("belt.axialDamping", Vr::Fixed(12), Ty::Real("AxialDampingCoefficient"), &["0.164"])
        .min("0")
        .id("BeltAxialDamping", "belt axial damping")
        .about("Axial Kelvin-Voigt damping (force per unit strain rate); each SDE gets value/l")),
    Item::One(param("belt.bendingStiffness", Vr::Fixed(13), Ty::Real("BendingStiffness"), &["2.08e-4"])
        .min("0")
        .id("BeltBendingStiffness", "belt bending stiffness")
        .about("Bending stiffness EI; each torsional SDE gets EI/l")),
    Item::One(param("belt.bendingDamping", Vr::Fixed(14), Ty::Real("BendingDampingCoefficient"), &["0"])
        .min("0")
        .id("BeltBendingDamping", "belt bending damping")
        .about("Bending damping; each torsional SDE gets value/l")),
    Item::One(param("belt.massPerLength", Vr::Fixed(15), Ty::Real("LinearDensity"), &["0.096"])
        .above("0")
        .id("BeltMassPerLength", "belt mass per length")
        .about("Mass per unit belt length")),
    Item::One(param("gravity", Vr::Fixed(16), Ty::Real("Acceleration"), &["9.81"])
        .min("0")
        .id("Gravity", "gravity")
        .about("Gravitational acceleration, acting in -y")),
    Item::One(param("contact.c1", Vr::Fixed(17), Ty::Real("QuadraticContactStiffness"), &["3.782e11"])
        .min("0")
        .id("ContactC1", "contact stiffness c1")
        .about("Quadratic contact stiffness per unit belt length (each body gets c1*l, eq. 9)")),
    Item::One(param("contact.c2", Vr::Fixed(18), Ty::Real("LinearContactStiffness"), &["8.125e7"])
        .min("0")
        .id("ContactC2", "contact stiffness c2")
        .about("Linear contact stiffness per unit belt length (each body gets c2*l, eq. 9)")),
    Item::One(param("contact.damping", Vr::Fixed(19), Ty::Real("ContactDampingCoefficient"), &["37500"])
        .min("0")
        .id("ContactDamping", "contact damping")
        .about("Contact damping per unit belt length (each body gets b*l, eq. 9)")),
    Item::One(param("contact.pMax", Vr::Fixed(20), Ty::Real("Length"), &["0"])
        .min("0")
        .id("ContactPMax", "contact damping ramp p_max")
        .about("Penetration at which contact damping is fully active (eq. 10-11); 0 = automatic: half of each pulley's equilibrium penetration under the preload, so the damping acts at any penetration (the paper's value is 1e-3)")),
    Item::One(param("friction.dv", Vr::Fixed(21), Ty::Real("Velocity"), &["1e-5"])
        .above("0")
        .id("FrictionDv", "friction transition velocity dv")
        .about("Transition velocity of the kubas2014 law")),
    Item::One(param("friction.creepMax", Vr::Fixed(22), Ty::Real("Length"), &["1e-4"])
        .above("0")
        .id("FrictionCreepMax", "friction creep displacement max")
        .about("Creep displacement at which static friction is fully developed (Delta_max)")),
    Item::One(param("friction.zoneFactor", Vr::Fixed(23), Ty::Real("Factor"), &["1"])
        .min("0")
        .id("FrictionZoneFactor", "friction zone factor")
        .about("Friction-coefficient factor in the modified-friction zone")),
    Item::One(param("solver.relTol", Vr::Fixed(24), Ty::Real("Tolerance"), &["1e-4"])
        .above("0")
        .below("1")
        .id("SolverRelTol", "relative tolerance")
        .about("Relative error tolerance of the integrator")),
    Item::One(param("solver.absTol", Vr::Fixed(25), Ty::Real("AbsoluteTolerance"), &["1e-6"])
        .above("0")
        .id("SolverAbsTol", "absolute tolerance")
        .about("Absolute error tolerance of the integrator, no single unit: each state's local error is compared with absTol + relTol*|state| in that state's own SI unit: body positions and creep displacements in m, body, pulley, decoupler and tensioner-arm angles and pivot friction deflections in rad, body velocities in m/s, body spins, pulley, rotor and arm speeds in rad/s, the work and dissipated energy in J (the impulses behind the mean-force outputs are not error-controlled). RKF45 weighs all states alike; the stiff method (solver.method = 2) counts the errors of body angles and spins 1000 times, and with the creep law of body velocities and tensioner arm rates 100 times, looser (they carry the bodies' artificial modes and the arms' response to them)")),
    Item::One(param("solver.initialStep", Vr::Fixed(26), Ty::Real("Time"), &["1e-7"])
        .above("0")
        .id("SolverInitialStep", "initial step")
        .about("First trial step size")),
    Item::Slots(
        Some("pulley[{j}]: parameters and inputs"),
        &[
        param("pulley[#].x", Vr::Pulley(1), Ty::Real("Position"), &["0", "0.515", "0"])
            .min("-1000")
            .max("1000")
            .id("PulleyX", "centre x")
            .about("Pulley centre x (slot {j})"),
        param("pulley[#].y", Vr::Pulley(2), Ty::Real("Position"), &["0", "0", "0.6", "0.8", "1.0", "1.2", "1.4", "1.6"])
            .min("-1000")
            .max("1000")
            .id("PulleyY", "centre y")
            .about("Pulley centre y (slot {j})"),
        param("pulley[#].radius", Vr::Pulley(3), Ty::Real("Length"), &["0.027", "0.027", "0.03"])
            .above("0")
            .id("PulleyRadius", "radius")
            .about("Pulley radius (slot {j})"),
        param("pulley[#].inertia", Vr::Pulley(4), Ty::Real("MomentOfInertia"), &["2.4e-4", "2.4e-4", "1e-4"])
            .above("0")
            .id("PulleyInertia", "inertia")
            .about("Pulley moment of inertia about its axis (slot {j})"),
        param("pulley[#].muStatic", Vr::Pulley(5), Ty::Real("FrictionCoefficient"), &["1.05"])
            .min("0")
            .id("PulleyMuStatic", "static friction coefficient")
            .about("Static friction coefficient belt-pulley (slot {j})"),
        param("pulley[#].muKinetic", Vr::Pulley(6), Ty::Real("FrictionCoefficient"), &["1.0"])
            .min("0")
            .id("PulleyMuKinetic", "kinetic friction coefficient")
            .about("Kinetic friction coefficient belt-pulley (slot {j})"),
        param("pulley[#].loadDamping", Vr::Pulley(7), Ty::Real("RotationalDampingConstant"), &["0", "0.5968310365946076", "0"])
            .min("0")
            .id("PulleyLoadDamping", "load damping")
            .about("Speed-proportional resistance: torque -loadDamping*omega (slot {j})"),
        param("pulley[#].torqueRamp", Vr::Pulley(8), Ty::Real("Torque"), &["-15", "0"])
            .id("PulleyTorqueRamp", "torque ramp")
            .about("Built-in drive torque reached at rampTime (added to the torque input; linear ramp from 0) (slot {j})"),
        param("pulley[#].omegaRamp", Vr::Pulley(9), Ty::Real("AngularVelocity"), &["0"])
            .id("PulleyOmegaRamp", "speed ramp")
            .about("Built-in speed reached at rampTime for a speed-driven pulley (added to omegaRef) (slot {j})"),
        param("pulley[#].rampTime", Vr::Pulley(10), Ty::Real("Time"), &["0.3"])
            .above("0")
            .id("PulleyRampTime", "ramp time")
            .about("Duration of the built-in linear ramp (slot {j})"),
        param("pulley[#].speedDriven", Vr::Pulley(11), Ty::Boolean, &["false"])
            .id("PulleySpeedDriven", "speed driven")
            .about("Pulley follows omegaRef (+omegaRamp profile) instead of its equation of motion (slot {j})"),
        param("pulley[#].backSide", Vr::Pulley(12), Ty::Boolean, &["false"])
            .id("PulleyBackSide", "back side")
            .about("Belt touches this pulley with its back (idler outside the loop), wrapping it clockwise (slot {j})"),
        input("pulley[#].torque", Vr::Pulley(20), Ty::Real("Torque"), &["0"])
            .about("External torque applied to pulley {j} (torque-driven pulleys)"),
        input("pulley[#].omegaRef", Vr::Pulley(21), Ty::Real("AngularVelocity"), &["0"])
            .about("Prescribed angular speed of pulley {j} (speed-driven pulleys)"),
        ],
    ),
    Item::Comment("scalar outputs"),
    Item::One(output("belt.minTension", Vr::Fixed(1001), Ty::Real("Force"))
        .about("Smallest SDE tension in the belt")),
    Item::One(output("belt.maxTension", Vr::Fixed(1002), Ty::Real("Force"))
        .about("Largest SDE tension in the belt")),
    Item::One(output("belt.length", Vr::Fixed(1003), Ty::Real("Length"))
        .about("Natural (unstretched) belt length chosen for the preload")),
    Item::One(calculated("belt.installedTension", Vr::Fixed(1016), Ty::Real("Force"))
        .about("Installation tension: belt.preload, or with belt.naturalLength given the tension at which the belt of that length fits the drive")),
    Item::One(output("probe.sdeForce", Vr::Fixed(1004), Ty::Real("Force"))
        .about("Force in the translational SDE ahead of (left of) the probe body (Fig. 15)")),
    Item::One(output("probe.x", Vr::Fixed(1005), Ty::Real("Position"))
        .about("Probe body position x")),
    Item::One(output("probe.y", Vr::Fixed(1006), Ty::Real("Position"))
        .about("Probe body position y")),
    Item::One(output("power.dissipated", Vr::Fixed(1007), Ty::Real("Power"))
        .deps(Deps::AllOmegaRef)
        .about("Instantaneous dissipated power of the whole drive, the rate of energy.dissipated: the belt's (SDE and contact damping, friction slip, and the creep law's creep springs' exchange with the normal force, which releases their energy as bodies leave a pulley and gains some as they land, so it can dip below zero) plus the loads' (load damping, decouplers); belt.powerLoss is the belt's alone")),
    Item::One(output("energy.dissipated", Vr::Fixed(1008), Ty::Real("Energy"))
        .about("Energy dissipated since start (the work of dampers, loads and friction less what the creep springs store)")),
    Item::One(output("energy.input", Vr::Fixed(1009), Ty::Real("Energy"))
        .about("Work done on the drive by applied torques since start")),
    Item::One(output("energy.kinetic", Vr::Fixed(1010), Ty::Real("Energy"))
        .deps(Deps::AllOmegaRef)
        .about("Kinetic energy of belt and pulleys")),
    Item::One(output("energy.potential", Vr::Fixed(1011), Ty::Real("Energy"))
        .about("Elastic (SDE, contact, creep springs) plus gravitational potential energy")),
    Item::One(discrete_output("solver.steps", Vr::Fixed(1012), Ty::Real("Count"))
        .about("Accepted integrator steps since start (Real to avoid 32-bit overflow)")),
    Item::One(discrete_output("solver.rejectedSteps", Vr::Fixed(1013), Ty::Real("Count"))
        .about("Rejected integrator steps since start")),
    Item::One(discrete_output("solver.rhsEvaluations", Vr::Fixed(1014), Ty::Real("Count"))
        .about("Right-hand-side evaluations since start")),
    Item::One(output("solver.lastStepSize", Vr::Fixed(1015), Ty::Real("Time"))
        .about("Last accepted integrator step size")),
    Item::Slots(
        Some("pulley[{j}]: outputs"),
        &[
        output("pulley[#].omega", Vr::PulleyOutput(1), Ty::Real("AngularVelocity"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Angular speed of pulley {j}"),
        output("pulley[#].angle", Vr::PulleyOutput(2), Ty::Real("Angle"))
            .about("Rotation angle of pulley {j}"),
        output("pulley[#].alpha", Vr::PulleyOutput(3), Ty::Real("AngularAcceleration"))
            .deps(Deps::Own(&["torque"]))
            .about("Angular acceleration of pulley {j} (also available as output derivative of omega)"),
        output("pulley[#].beltTorque", Vr::PulleyOutput(4), Ty::Real("Torque"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Torque the belt exerts on pulley {j}"),
        output("pulley[#].driveTorque", Vr::PulleyOutput(5), Ty::Real("Torque"))
            .deps(Deps::Own(&["torque", "omegaRef"]))
            .about("Torque the drive must supply to pulley {j} if it is speed-driven (0 for torque-driven)"),
        output("pulley[#].hubForce.x", Vr::PulleyOutput(6), Ty::Real("Force"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Force of the belt on the hub of pulley {j}, x"),
        output("pulley[#].hubForce.y", Vr::PulleyOutput(7), Ty::Real("Force"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Force of the belt on the hub of pulley {j}, y"),
        output("pulley[#].slip", Vr::PulleyOutput(8), Ty::Real("Ratio"))
            .deps(Deps::FirstAndOwn)
            .about("Speed loss of the surface of pulley {j} relative to pulley 1: 1 - v_{j}/v_1"),
        output("pulley[#].wrapAngle", Vr::PulleyOutput(9), Ty::Real("Angle"))
            .about("Wrap angle of the belt path on pulley {j} (layout)"),
        ],
    ),
    Item::Comment("probe and span outputs"),
    Item::Array(output("probe.normalForce[#]", Vr::Array(1710), Ty::Real("Force"))
        .about("Normal contact force of pulley {j} on the probe body (Fig. 16)")),
    Item::Array(output("probe.frictionForce[#]", Vr::Array(1720), Ty::Real("Force"))
        .deps(Deps::AllOmegaRef)
        .about("Friction force of pulley {j} on the probe body (Fig. 17)")),
    Item::Array(output("probe.slipVelocity[#]", Vr::Array(1730), Ty::Real("Velocity"))
        .deps(Deps::AllOmegaRef)
        .about("Tangential relative velocity surface of pulley {j} - probe body (Fig. 18)")),
    Item::Array(output("span[#].tension", Vr::Array(1740), Ty::Real("Force"))
        .about("Tension in the middle SDE of the free span from pulley {j} to the next pulley of the loop (pulley 1 after the last)")),
    Item::Array(output("span[#].slip", Vr::Array(1750), Ty::Real("Ratio"))
        .deps(Deps::Span)
        .about("Slip across span {j}, from pulley {j} to the next pulley of the loop (pulley 1 after the last): surface speed loss 1 - v_next/v_{j}")),
    Item::One(param("friction.creepDampingTime", Vr::Fixed(27), Ty::Real("Time"), &["3e-4"])
        .min("0")
        .max("1")
        .id("FrictionCreepDampingTime", "friction creep damping time")
        .about("Relaxation time of the creep law's spring: its damper is this time the spring's slope (Kelvin-Voigt); 0 = undamped")),
    Item::Array(param("pulley[#].grooveAngle", Vr::Pulley(30), Ty::Real("Angle"), &["0"])
        .min("0")
        .below("3.141592653589793")
        .id("PulleyGrooveAngle", "groove angle")
        .about("Included angle 2 beta of the V-ribbed groove, 0 = flat: the ribs carry friction with mu/sin(beta) (muStatic, muKinetic are the flat-pulley coefficients); the belt back on a back-side idler stays flat (slot {j})")),
    Item::Array(output("span[#].midDeflection", Vr::Array(1760), Ty::Real("Length"))
        .about("Transverse deflection of the belt at the fixed mid-point of free span {j}, from the straight common tangent of the mounted path (positive to the left of the travel from pulley {j} to the next)")),
    Item::Array(output("span[#].midDeflectionRate", Vr::Array(1770), Ty::Real("Velocity"))
        .about("Rate of span[{j}].midDeflection (at the fixed mid-point)")),
    Item::Slots(
        None,
        &[
        param("pulley[#].decoupler", Vr::Pulley(13), Ty::Boolean, &["false"])
            .id("PulleyDecoupler", "decoupler")
            .about("A one-way decoupler sits between the hub (driven by the belt) and a rotor: torsion spring and damper in series with a one-way clutch; the torque input, torqueRamp and loadDamping then act on the rotor (slot {j})"),
        param("pulley[#].decoupler.clockwise", Vr::Pulley(14), Ty::Boolean, &["false"])
            .id("PulleyDecouplerClockwise", "decoupler driving clockwise")
            .about("The decoupler clutch drives the rotor clockwise (negative omega); false: counterclockwise. Set it to the sense the belt drives this pulley in (slot {j})"),
        param("pulley[#].decoupler.stiffness", Vr::Pulley(31), Ty::Real("TorsionalStiffness"), &["10"])
            .min("0")
            .id("PulleyDecouplerStiffness", "decoupler stiffness")
            .about("Torsional stiffness of the decoupler spring (slot {j})"),
        param("pulley[#].decoupler.damping", Vr::Pulley(32), Ty::Real("RotationalDampingConstant"), &["0.02"])
            .min("0")
            .id("PulleyDecouplerDamping", "decoupler damping")
            .about("Viscous damping parallel to the decoupler spring, > 0: the spring relaxes through it while the clutch overruns (slot {j})"),
        param("pulley[#].rotor.inertia", Vr::Pulley(33), Ty::Real("MomentOfInertia"), &["3e-3"])
            .min("0")
            .id("PulleyRotorInertia", "rotor inertia")
            .about("Moment of inertia of the rotor behind the decoupler (slot {j})"),
        ],
    ),
    Item::Slots(
        None,
        &[
        output("pulley[#].rotor.omega", Vr::PulleyOutput(10), Ty::Real("AngularVelocity"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Angular speed of the rotor behind the decoupler of pulley {j} (the pulley speed when it has none)"),
        output("pulley[#].decoupler.torque", Vr::PulleyOutput(11), Ty::Real("Torque"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Torque the decoupler clutch of pulley {j} transmits to its rotor, in the clutch sense (>= 0; 0 without a decoupler)"),
        ],
    ),
    Item::Slots(
        None,
        &[
        param("pulley[#].tensioner", Vr::Pulley(15), Ty::Boolean, &["false"])
            .id("PulleyTensioner", "tensioner")
            .about("The pulley sits on an automatic tensioner arm pivoting about pulley[j].arm.pivot.x/y; pulley[j].x/y is its centre as drawn (and as mounted, unless arm.nominalTorque gives the spring), the arm length the distance from the pivot to it; the pulley turns with the belt like an idler (slot {j})"),
        param("pulley[#].arm.pivot.x", Vr::Pulley(34), Ty::Real("Position"), &["0"])
            .min("-1000")
            .max("1000")
            .id("PulleyArmPivotX", "tensioner pivot x")
            .about("x of the tensioner arm's pivot (slot {j})"),
        param("pulley[#].arm.pivot.y", Vr::Pulley(35), Ty::Real("Position"), &["0"])
            .min("-1000")
            .max("1000")
            .id("PulleyArmPivotY", "tensioner pivot y")
            .about("y of the tensioner arm's pivot (slot {j})"),
        param("pulley[#].arm.inertia", Vr::Pulley(36), Ty::Real("MomentOfInertia"), &["1e-3"])
            .min("0")
            .id("PulleyArmInertia", "tensioner arm inertia")
            .about("Moment of inertia of tensioner arm and pulley about the pivot, > 0 (slot {j})"),
        param("pulley[#].arm.stiffness", Vr::Pulley(37), Ty::Real("TorsionalStiffness"), &["40"])
            .min("0")
            .id("PulleyArmStiffness", "tensioner spring stiffness")
            .about("Torsional stiffness (rate) of the tensioner spring, > 0; its free angle is set by the mounting so that it balances the belt preload, or follows from arm.nominalTorque at arm.nominalAngle (slot {j})"),
        param("pulley[#].arm.damping", Vr::Pulley(38), Ty::Real("RotationalDampingConstant"), &["0"])
            .min("0")
            .id("PulleyArmDamping", "tensioner arm damping")
            .about("Viscous damping of the tensioner arm about its pivot (slot {j})"),
        param("pulley[#].arm.friction", Vr::Pulley(39), Ty::Real("Torque"), &["0"])
            .min("0")
            .id("PulleyArmFriction", "tensioner pivot friction")
            .about("Coulomb friction torque of the tensioner pivot, reached once the arm slides beyond its presliding deflection (arm.preslidingAngle); it gives the asymmetric damping of automotive tensioners (slot {j})"),
        ],
    ),
    Item::Slots(
        None,
        &[
        output("pulley[#].arm.angle", Vr::PulleyOutput(12), Ty::Real("Angle"))
            .about("Angle of the tensioner arm of pulley {j} from its mounted position, counterclockwise positive (0 without an arm)"),
        output("pulley[#].arm.omega", Vr::PulleyOutput(13), Ty::Real("AngularVelocity"))
            .about("Angular speed of the tensioner arm of pulley {j} (0 without an arm)"),
        output("pulley[#].arm.springTorque", Vr::PulleyOutput(14), Ty::Real("Torque"))
            .about("Torque of the tensioner spring on the arm of pulley {j}, counterclockwise positive (0 without an arm)"),
        ],
    ),
    Item::Array(calculated("pulley[#].arm.freeAngle", Vr::PulleyOutput(15), Ty::Real("Angle"))
        .about("Free angle of the tensioner spring of pulley {j} from the mounted arm position: found by the mounting so that the spring balances the moment of the belt's hub force about the pivot at belt.preload, or with arm.nominalTorque given the one that spring has (0 without an arm)")),
    Item::Slots(
        None,
        &[
        output("pulley[#].meanBeltTorque", Vr::PulleyOutput(20), Ty::Real("Torque"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Mean over the last communication step of the torque the belt exerts on pulley {j} (its value at the current time before the first step)"),
        output("pulley[#].meanDriveTorque", Vr::PulleyOutput(21), Ty::Real("Torque"))
            .deps(Deps::Own(&["torque", "omegaRef"]))
            .about("Mean over the last communication step of the torque the drive supplies to pulley {j} if it is speed-driven (0 for torque-driven; the current value before the first step)"),
        output("pulley[#].meanHubForce.x", Vr::PulleyOutput(22), Ty::Real("Force"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Mean over the last communication step of the force of the belt on the hub of pulley {j}, x (the current value before the first step)"),
        output("pulley[#].meanHubForce.y", Vr::PulleyOutput(23), Ty::Real("Force"))
            .deps(Deps::Own(&["omegaRef"]))
            .about("Mean over the last communication step of the force of the belt on the hub of pulley {j}, y (the current value before the first step)"),
        output("pulley[#].meanAlpha", Vr::PulleyOutput(24), Ty::Real("AngularAcceleration"))
            .deps(Deps::Own(&["torque"]))
            .about("Mean angular acceleration of pulley {j} over the last communication step: its change of speed over the step divided by the step (alpha before the first step)"),
        ],
    ),
    Item::One(output("belt.powerLoss", Vr::Fixed(1800), Ty::Real("Power"))
        .deps(Deps::AllOmegaRef)
        .about("Power dissipated in the belt (>= 0): its axial, bending and transverse dampers, contact damping and friction slip; not the creep springs' exchange with the normal force (not signed at an instant, a loss over whole passes of the bodies: power.dissipated holds it) and not the loads' power (power.dissipated adds it)")),
    Item::One(param("belt.shearDampingFactor", Vr::Fixed(28), Ty::Real("Factor"), &["1"])
        .min("0")
        .id("BeltShearDampingFactor", "belt shear damping factor")
        .about("Damping of each spring-damper element across its gap (the joint's shear: the bodies pitching against each other) as a multiple of belt.axialDamping; 1 = isotropic Kelvin-Voigt element, its damper acting on the gap vector as its spring does; 0 = the paper's damper along the gap only (eq. 20), which leaves the bodies' pitching in the spans undamped")),
    Item::One(param("belt.transverseDamping", Vr::Fixed(29), Ty::Real("DampingRate"), &["25"])
        .min("0")
        .id("BeltTransverseDamping", "belt transverse damping")
        .about("Damping of the belt's motion across its length (the spans' vibration: air and the span ends), per unit mass: each body's centre velocity across its axis is damped by its mass times this rate; a span mode of frequency f gets the damping ratio value/(4 pi f) (the default: 2 % at 100 Hz); no loss in steady running; 0 = none (the paper's model)")),
    Item::Comment("interval outputs: over the last communication step, from the integrator's steps"),
    Item::Array(output("span[#].meanTension", Vr::Array(1810), Ty::Real("Force"))
        .about("Mean tension of span {j} (as span[{j}].tension reads it) over the last communication step: the trapezoidal rule over the integrator's steps (its value at the current time before the first step)")),
    Item::Array(output("span[#].minTension", Vr::Array(1820), Ty::Real("Force"))
        .about("Smallest tension of span {j} over the last communication step, at the ends of the integrator's steps")),
    Item::Array(output("span[#].maxTension", Vr::Array(1830), Ty::Real("Force"))
        .about("Largest tension of span {j} over the last communication step, at the ends of the integrator's steps")),
    Item::One(output("belt.intervalMinTension", Vr::Fixed(1801), Ty::Real("Force"))
        .about("Smallest SDE tension anywhere in the belt over the last communication step, at the ends of the integrator's steps (belt.minTension is the instant's)")),
    Item::Slots(
        None,
        &[
        output("pulley[#].arm.meanSpringTorque", Vr::PulleyOutput(25), Ty::Real("Torque"))
            .about("Mean torque of the tensioner spring on the arm of pulley {j} over the last communication step (0 without an arm)"),
        ],
    ),

    Item::Slots(
        None,
        &[
            param("pulley[#].arm.stops", Vr::Pulley(40), Ty::Boolean, &["false"])
                .id("PulleyArmStops", "tensioner end stops")
                .about("The tensioner arm has end stops at arm.minAngle and arm.maxAngle: past them a stiff, damped contact (arm.stopStiffness, arm.stopDamping) pushes it back (slot {j})"),
            param("pulley[#].arm.minAngle", Vr::Pulley(41), Ty::Real("Angle"), &["-0.35"])
                .min("-3.141592653589793")
                .max("0")
                .id("PulleyArmMinAngle", "tensioner lower stop angle")
                .about("Angle of the tensioner arm's lower end stop from the arm as drawn (pulley[j].x/y: the mounted position unless arm.nominalTorque is given), counterclockwise positive; the drawn arm lies between the stops (used when arm.stops is set) (slot {j})"),
            param("pulley[#].arm.maxAngle", Vr::Pulley(42), Ty::Real("Angle"), &["0.35"])
                .min("0")
                .max("3.141592653589793")
                .id("PulleyArmMaxAngle", "tensioner upper stop angle")
                .about("Angle of the tensioner arm's upper end stop from the arm as drawn (pulley[j].x/y: the mounted position unless arm.nominalTorque is given), counterclockwise positive (used when arm.stops is set) (slot {j})"),
            param("pulley[#].arm.stopStiffness", Vr::Pulley(43), Ty::Real("TorsionalStiffness"), &["0"])
                .min("0")
                .id("PulleyArmStopStiffness", "tensioner stop stiffness")
                .about("Contact stiffness of the tensioner arm's end stops; 0 = automatic: 100 times arm.stiffness (the arm yields a hundredth of what its spring would) (slot {j})"),
            param("pulley[#].arm.stopDamping", Vr::Pulley(44), Ty::Real("RotationalDampingConstant"), &["0"])
                .min("0")
                .id("PulleyArmStopDamping", "tensioner stop damping")
                .about("Contact damping of the tensioner arm's end stops, built up over the first 1e-3 rad of contact; 0 = automatic: damping ratio 0.5 of the arm on the stop, sqrt(stopStiffness * arm.inertia) (slot {j})"),
        ],
    ),
    Item::Slots(
        None,
        &[
            param("pulley[#].arm.nominalTorque", Vr::Pulley(46), Ty::Real("Torque"), &["0"])
                .min("0")
                .id("PulleyArmNominalTorque", "tensioner nominal spring torque")
                .about("The tensioner spring as a catalogue gives it: the torque it exerts at arm.nominalAngle, pressing the pulley into the belt (a magnitude); with arm.stiffness as its rate the spring's free angle follows, and the mounting finds where the arm sits (arm.installedAngle) at belt.preload, or with belt.naturalLength together with the tension. 0 (default) = the spring's free angle follows from belt.preload with the arm where it is drawn (slot {j})"),
            param("pulley[#].arm.nominalAngle", Vr::Pulley(45), Ty::Real("Angle"), &["0"])
                .min("-3.141592653589793")
                .max("3.141592653589793")
                .id("PulleyArmNominalAngle", "tensioner nominal arm angle")
                .about("Arm angle at which the spring exerts arm.nominalTorque, from the arm as drawn (pulley[j].x/y), counterclockwise positive; used only with arm.nominalTorque > 0 (slot {j})"),
        ],
    ),
    Item::Slots(
        None,
        &[
            param("pulley[#].arm.hubFriction", Vr::Pulley(47), Ty::Real("FrictionCoefficient"), &["0"])
                .min("0")
                .id("PulleyArmHubFriction", "tensioner hub-load friction coefficient")
                .about("Friction coefficient of the tensioner's hub-load (asymmetric) damping: a pivot friction torque arm.hubFriction x |hub force| x arm.frictionRadius beside the constant arm.friction, with the same presliding law (arm.preslidingAngle); it grows with the belt's load on the pulley, as the damping of automotive tensioners does (0 = none) (slot {j})"),
            param("pulley[#].arm.frictionRadius", Vr::Pulley(48), Ty::Real("Length"), &["0"])
                .min("0")
                .id("PulleyArmFrictionRadius", "tensioner friction radius")
                .about("Radius at which the tensioner's hub-load friction acts (its damping bushing or friction shoe), > 0 when arm.hubFriction is (slot {j})"),
            param("pulley[#].arm.preslidingAngle", Vr::Pulley(49), Ty::Real("Angle"), &["2e-4"])
                .min("1e-7")
                .max("0.01")
                .id("PulleyArmPreslidingAngle", "tensioner presliding angle")
                .about("Presliding angle of the tensioner's pivot friction (arm.friction and arm.hubFriction): the pivot's contact deflects elastically by up to this angle under the friction torque before it slides (an elasto-plastic presliding law), so a ripple far smaller than it does not make the arm slip and a held arm does not creep. Default 2e-4 rad, about 3 micrometres at a 15 mm bushing radius, the presliding displacement of metal and polymer contacts (slot {j})"),
        ],
    ),
    Item::Array(calculated("pulley[#].arm.installedAngle", Vr::PulleyOutput(26), Ty::Real("Angle"))
        .about("Angle of the installed tensioner arm of pulley {j} from where it is drawn (pulley[j].x/y), counterclockwise positive: found by the mounting when the spring is given by arm.nominalTorque, else 0. arm.angle and arm.freeAngle count from the installed arm: add this angle to read them from the drawing (slot {j})")),
];
