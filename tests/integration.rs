//! The integration tests, one module per file, in one test binary (one link, `tests/common`
//! compiled once): `cargo test --release --test integration plates::` runs one file's.
//! `tests/architecture.rs`, `tests/petsc_layer.rs` and `tests/tutorial.rs` stay binaries of
//! their own (no MPI launch; the tutorial in the slow tier).

#[path = "accuracy_line.rs"]
mod accuracy_line;
#[path = "aspiration.rs"]
mod aspiration;
#[path = "axisymmetric.rs"]
mod axisymmetric;
#[path = "bad_input.rs"]
mod bad_input;
mod common;
#[path = "force_control.rs"]
mod force_control;
#[path = "force_tools.rs"]
mod force_tools;
#[path = "io_fields.rs"]
mod io_fields;
#[path = "lab_input.rs"]
mod lab_input;
#[path = "laplace.rs"]
mod laplace;
#[path = "laplace_drop.rs"]
mod laplace_drop;
#[path = "medium.rs"]
mod medium;
#[path = "neo_hookean.rs"]
mod neo_hookean;
#[path = "plate_paths.rs"]
mod plate_paths;
#[path = "plates.rs"]
mod plates;
#[path = "plot.rs"]
mod plot;
#[path = "remodelling.rs"]
mod remodelling;
#[path = "restart.rs"]
mod restart;
#[path = "study.rs"]
mod study;
#[path = "surface.rs"]
mod surface;
#[path = "sweep.rs"]
mod sweep;
#[path = "tools.rs"]
mod tools;
#[path = "verification.rs"]
mod verification;
