//! The three representations (§3.3–§3.5), all built from a skeleton's nodes and node frames alone:
//! strand curves (n control points each), cluster tubes (4n) and patch strips (2n).
//!
//! The control-point builders are pure functions of one chain; [`geometry`] turns whole grooms into
//! NURBS curves and surfaces, polylines and triangle meshes.

mod cluster;
pub mod drawn;
pub mod geometry;
mod patch;
pub mod roots;
mod strand;

pub use cluster::{CLUSTER_POINTS_PER_NODE, cluster_control_points, cluster_radius_at};
pub use patch::{PATCH_POINTS_PER_NODE, patch_control_points};
pub use strand::strand_control_points;
