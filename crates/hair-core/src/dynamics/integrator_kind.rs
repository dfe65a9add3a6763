//! The four time integrators a simulation can run, by name ([`IntegratorKind`]).

crate::named_enum! {
    /// The time integrator of a simulation.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub enum IntegratorKind {
        /// Semi-implicit (symplectic) Euler on all forces, then projection onto the segment lengths
        /// (follow-the-leader positions, relative velocity along each segment removed): the paper's model.
        SemiImplicitEuler = "semi-implicit-euler",
        /// Position-based: Verlet prediction under external forces, angular springs as shape targets,
        /// follow-the-leader lengths with dynamic velocity correction (Müller, Kim, Chentanez 2012).
        PositionBased = "position-based",
        /// Linearised backward Euler of spring, damping and drag forces along each chain (a banded
        /// block solve per chain), then the same length projection as the semi-implicit integrator.
        LinearImplicit = "linear-implicit",
        /// XPBD with small steps (Macklin et al. 2016, 2019): prediction under external forces with
        /// implicit drag, line-searched Newton steps of each chain's angular springs together as
        /// compliant constraints (compliance `1/k`, so any stiffness is stable), then the exact
        /// length projection and a dissipative damping sweep.
        Xpbd = "xpbd",
    }
}

impl IntegratorKind {
    /// The default integrator, XPBD at 8 substeps per 60 Hz frame, doubled up to 32 where the hair
    /// moves fast ([`SimulationSettings::recommended`](crate::dynamics::SimulationSettings::recommended)): on the stability map
    /// (`hairlod stability`, `docs/dynamics.md`) it has the most stable runs of the four and no
    /// unstable one from 1/1000 s to 1/15 s up to 100× the styles' stiffness; at 60 Hz its
    /// recommended substeps are stable in all 20 scenarios; on paper-curly in the seeded wind it
    /// is 0.03 px from the converged motion, against 0.40 px for linear-implicit ×4
    /// (`hairlod accuracy --wind`, `docs/accuracy.md`). Linear-implicit,
    /// the default until 2026-11-28, stays available; the position-based integrator is the fast
    /// alternative where its damped look is acceptable.
    pub const DEFAULT: IntegratorKind = IntegratorKind::Xpbd;

    /// Whether this integrator steps chains in runs of up to eight through a lane kernel (the
    /// position-based and XPBD integrators; their chains have at most
    /// [`MAX_CHAIN_NODES`](crate::dynamics::MAX_CHAIN_NODES) nodes) rather than one at a time.
    pub fn steps_lanes(self) -> bool {
        matches!(self, IntegratorKind::PositionBased | IntegratorKind::Xpbd)
    }
}
