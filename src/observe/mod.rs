//! What a run observes of its converged states, above the equations (`physics`) and below the
//! output (`io`) and the run (`driver`): the observers that turn a state into a step's
//! `history.csv` values and fields (io's record types), the plates experiment's observables and its Laplace analysis,
//! probes, the remodelling summary, the run's largest pore pressure, and the exact solutions of the verification scenes;
//! each declares its `history.csv` columns once (name, unit, meaning, value), and `columns` lists them all for the docs.

pub mod analytic;
pub mod columns;
pub mod experiment;
pub mod laplace;
pub mod observers;
pub mod pressure_peak;
pub mod probe;
pub mod remodelling_summary;
pub mod verification;
