//! Run output: the run directory, per-step field files (HDF5 + XDMF for ParaView), the
//! `history.csv` log (and the observables read from it) and the checkpoint files; `format`
//! writes their numbers (and the log's).

pub(crate) mod checkpoint;
pub mod fields;
mod format;
pub(crate) mod history;
pub(crate) mod observable;
pub(crate) mod recorder;
pub(crate) mod rundir;

pub(crate) use format::{fmt_duration, fmt_real, fmt_short, fmt_significant, fmt_time};
