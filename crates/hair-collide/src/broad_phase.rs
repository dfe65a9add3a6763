//! How the collision stage finds the hair near a body: the paper's hierarchies, the body's
//! distance field as a cull before the same exact tests, or contacts from the field itself
//! ([`BroadPhase`]).

hair_core::named_enum! {
    /// How [`CollisionSolver::before_step`](crate::CollisionSolver::before_step) finds the
    /// segments that touch a body, and how
    /// [`CollisionSolver::after_step`](crate::CollisionSolver::after_step) the nodes to project.
    /// The first two give the same contacts and the same projections, bit for bit: they differ
    /// in cost only. The third finds the contacts from the field's distance and gradient
    /// instead of the triangles, with the projections of the other two.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub enum BroadPhase {
        /// The paper's hierarchies (§5.3): each of the hair's swept-sphere volumes descends the
        /// body's triangle tree ([`query_body_volumes`](crate::query_body_volumes)), in chunks
        /// side by side on the cores, to the exact triangle tests; the hair's own tree is
        /// refitted only for hair–hair contact. Faster than `DistanceField` on hair that lies on
        /// the head: the exact tests of the segments near the surface dominate, and the field's
        /// cull adds lookups on top of them.
        Hierarchies = "hierarchies",
        /// The body's [`DistanceField`](crate::DistanceField) clears the segments and nodes that
        /// are far from it in a few lookups each; only those near the surface get the exact
        /// tests, against the triangles their bounds overlap. The cost follows the hair near the
        /// body; the hair's hierarchy is refitted only when hair–hair contact needs it. Builds
        /// the field once per mesh (about 0.3 s for the procedural head in a release build).
        DistanceField = "distance-field",
        /// Contacts from the body's [`DistanceField`](crate::DistanceField) itself: a segment
        /// touches where the field's interpolated signed distance at a few samples of its core
        /// comes within its radius, and its normal is the field's gradient there
        /// ([`query_body_field`](crate::query_body_field)), as TressFX and Frostbite collide
        /// hair; no triangle is visited unless the field cannot decide. The contacts differ from
        /// the triangles' by the samples' error (see `field_contacts.rs`); the positional
        /// guarantee is the same exact projection as the others'. The default: measured on the
        /// paper's tables at the same SSIMs to four places, with collision 1.3–2× cheaper per
        /// level, and 4.8× cheaper on the 25-head crowd (`docs/collision.md`). Builds the field
        /// once per mesh (0.38 s for the procedural head in a release build).
        #[default]
        FieldContacts = "field-contacts",
    }
}
