"""The study scripts' shared core (the scripts in scripts/ are thin command lines over it).

  * cases       running cases: a study file of [[case]] entries, ONE `poroplast sweep` for them
                into the case store DIR/cases (the sweep keeps the cases: completed ones are
                skipped, interrupted ones resumed); the results read from its summary.csv;
                the scripts' rank options; scenes' values
  * levels      grids of overrides, mesh levels (h with the other sizes scaled), step levels
  * history     reading a run: history.csv, timings.txt, a column at a time
  * richardson  observed orders, Richardson corrections and extrapolation with error bars
  * convergence the convergence-study design (mesh levels x step levels) and its extrapolation
  * refs        scripts/data/references.csv, the converged values
  * closed forms to check the solver against, computed independently of it (issue 53):
                consolidation_refs (Terzaghi's settlement), indentation_refs (Hertz, Sneddon's
                sphere, Hu et al.'s poroelastic relaxation), aspiration_refs (Theret's elastic
                half-space: the wall function Φ(η) computed), capillary_refs (a liquid drop at a
                pipette: threshold and static shape)
  * fields      observables of a run's fields (region means, the pressure bubble) and events
  * labels      figure labels in the docs' units
  * tables      CSV tables and the Pareto front
  * fit         least squares over an abstract model: Levenberg-Marquardt (several searches in
                step, one batch per iteration), re-weighting, standard errors, Wald intervals
  * profile     profile-likelihood intervals, the others re-optimised by fit's LM
  * fitstats    noise models and their weights, quantiles; measured: a lab's data file;
                units: units in column names, the one g (9.81 m/s²);
                identify: identifiability at the start; experiments: a calibration's
                experiments file and parameters
  * runmodel    a fit's model: the experiments' runs at parameter points; fitplots: its figures
  * synthetic   the calibration's synthetic experiment: the meridian case, its truths, noisy data sets
  * coverage    a calibration's confidence intervals, whether they hold the truth, coverage rates

Observables of histories (`max:COL`, `COL@T`, ...) are evaluated by `poroplast sweep` alone
(src/io/observable.rs); the scripts read them from the summary.
"""
