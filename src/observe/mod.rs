//! What a run observes of its converged states, above the equations (`physics`) and below the
//! output (`io`) and the run (`driver`): the observers that turn a state into a step's
//! `history.csv` values and fields (io's record types), the plates experiment's observables and its Laplace analysis,
//! probes, the remodelling summary, the run's largest pore pressure, and the exact solutions of the verification scenes;
//! each declares its `history.csv` columns once (name, unit, meaning, value), and `columns` lists them all for the docs.

pub(crate) mod analytic;
pub(crate) mod aspiration;
pub(crate) mod columns;
pub(crate) mod experiment;
pub(crate) mod force_control;
pub(crate) mod laplace;
pub(crate) mod observers;
pub(crate) mod pressure_peak;
pub(crate) mod probe;
pub(crate) mod remodelling_summary;
pub(crate) mod tools;
pub(crate) mod verification;
