//! What the stiff integrator ([`crate::solver::rosenbrock`]) needs of a
//! system beyond an [`OdeSystem`]: its Jacobian, the iteration matrix
//! `I - c J` factored and solved, and optionally its energy balance
//! (the step's energy check). The model implements it; the method reads
//! nothing else of the model.

use crate::solver::step_control::OdeSystem;

/// An ODE whose Jacobian (or an approximation of it) can be formed and whose
/// iteration matrix `I - c J` can be factored and solved.
pub trait StiffSystem: OdeSystem {
    /// The Jacobian's storage.
    type Jacobian: Clone + std::fmt::Debug + PartialEq;
    /// The factored iteration matrix's storage.
    type Matrix: Clone + std::fmt::Debug + PartialEq;
    /// Storage for a Jacobian.
    fn new_jacobian(&self) -> Self::Jacobian;
    /// Storage for an iteration matrix.
    fn new_matrix(&self) -> Self::Matrix;
    /// Evaluates the Jacobian at (t, y).
    fn jacobian(&self, t: f64, y: &[f64], jac: &mut Self::Jacobian);
    /// Sets the entries of a kept Jacobian that depend on the time alone
    /// (the inputs) to their values at the start `t` of the step about to
    /// be tried; called before every trial step. Entries outside the
    /// factored matrix only (rows nothing depends on): the factorization
    /// stays valid.
    fn step_rows(&self, _t: f64, _jac: &mut Self::Jacobian) {}
    /// Factors `I - c J`; false if it is singular.
    fn factor(&self, jac: &Self::Jacobian, c: f64, m: &mut Self::Matrix) -> bool;
    /// Overwrites `b` with the solution x of `(I - c J) x = b`.
    fn solve(&self, jac: &Self::Jacobian, m: &mut Self::Matrix, b: &mut [f64]);
    /// Which components enter the error norm (1) and which not (0): those
    /// that only carry the fast modes the method is meant to damp; weights
    /// in between may depend on the relative tolerance `rel_tol`.
    fn error_mask(&self, _rel_tol: f64, mask: &mut [f64]) {
        mask.fill(1.0);
    }
    /// The energy balance of state `y`, if the system books its energy:
    /// the input work less the dissipated and the stored energy, constant
    /// along the exact flow (see [`EnergyBalance`]).
    fn energy_balance(&self, _y: &[f64]) -> Option<EnergyBalance> {
        None
    }
    /// dy = f(t, y) and the energy balance of `y` ([`Self::energy_balance`])
    /// from one evaluation; `dy` must be the right-hand side's to the last
    /// bit. By default the right-hand side, then the balance.
    fn rhs_balance(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Option<EnergyBalance> {
        self.rhs(ws, t, y, dy);
        self.energy_balance(y)
    }
    /// Appends the Jacobian's numbers to `out` / reads them back (false if
    /// they do not fit), for saved states.
    fn save_jacobian(&self, jac: &Self::Jacobian, out: &mut Vec<f64>);
    /// Reads what `save_jacobian` wrote; false if it does not fit.
    fn load_jacobian(&self, jac: &mut Self::Jacobian, src: &[f64]) -> bool;
}

/// A state's energy balance (see [`StiffSystem::energy_balance`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyBalance {
    /// Input work less dissipated energy less stored energy [J]: its change
    /// over a step is the step's energy residual, zero for the exact flow.
    pub balance: f64,
    /// The energy the residual is measured against [J]: a step's residual
    /// is at tolerance when it is relTol times this (for the belt: the
    /// belt's own stored energy, [`crate::model::system::StoredEnergy::belt`]).
    pub scale: f64,
    /// The size of the terms the balance sums [J], for its round-off.
    pub magnitude: f64,
}
