//! The base skeleton (§3.2): chains of nodes with fixed segment lengths and rest angles (θ0, φ0),
//! stored flat, struct-of-arrays, with an offsets array.
//!
//! Conventions, used by every crate of hairlod:
//! - chain `c` owns nodes `offsets[c]..offsets[c + 1]`; node 0 of a chain is its root;
//! - per-node arrays hold, at node `i ≥ 1`, the data of the *segment that ends at node `i`*
//!   (from node `i − 1` to node `i`): its rest length and its rest angles; at the root they are 0;
//! - the rest angles of node `i` give the direction of segment `i` in the frame of segment `i − 1`
//!   (for `i = 1`, the root frame), as [`Frame::direction`](crate::Frame::direction)`(θ0, φ0)`;
//! - the frame of segment `i` is the frame of segment `i − 1` carried to the new direction by the
//!   smallest rotation (discrete parallel transport), so the chain is twist-free;
//! - the frame *at a node* is halfway between the frames of its two segments
//!   ([`node_frames`]); the root uses the root frame and the tip the last segment's frame.

mod chain;
mod rest;

pub use chain::{ChainAngles, build_chain, measure_chain, node_frames};
pub use rest::SkeletonRest;
