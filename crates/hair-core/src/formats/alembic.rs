//! Alembic `.abc` curves (Ogawa archives) through the `ogawa-rs` crate.
