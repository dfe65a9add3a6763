//! How the collision stage finds the hair near a body: the paper's hierarchies or the body's
//! distance field ([`BroadPhase`]). The same contacts either way; only the cost differs.

hair_core::named_enum! {
    /// How [`CollisionSolver::before_step`](crate::CollisionSolver::before_step) finds the
    /// segments that touch a body, and how
    /// [`CollisionSolver::after_step`](crate::CollisionSolver::after_step) the nodes to project.
    /// Both give the same contacts and the same projections, bit for bit: they differ in cost
    /// only.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub enum BroadPhase {
        /// The paper's hierarchies (§5.3, the default): each of the hair's swept-sphere volumes
        /// descends the body's triangle tree ([`query_body_volumes`](crate::query_body_volumes)),
        /// in chunks side by side on the cores; the hair's own tree is refitted only for hair–hair
        /// contact. Measured faster than the field on hair that lies on the head
        /// (`docs/collision.md`): the exact tests of the segments near the surface dominate, and
        /// the field adds lookups on top of them.
        #[default]
        Hierarchies = "hierarchies",
        /// The body's [`DistanceField`](crate::DistanceField) clears the segments and nodes that
        /// are far from it in a few lookups each; only those near the surface get the exact
        /// tests, against the triangles their bounds overlap. The cost follows the hair near the
        /// body; the hair's hierarchy is refitted only when hair–hair contact needs it. Builds
        /// the field once per mesh (about 0.3 s for the procedural head in a release build).
        DistanceField = "distance-field",
    }
}
