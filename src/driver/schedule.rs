//! The time-step schedule: steps chosen by a local error estimate or by geometric growth,
//! landing on the loading's kinks, the output times and the end.

/// Time steps: chosen by a local error estimate (with `tol`) or by geometric growth, up to
/// dt_max, landing exactly on t_end and the `land_on` times, and restarting from dt0 after each
/// of the `kinks` (times where the loading rate jumps).
#[derive(Debug, Clone)]
pub(crate) struct Schedule {
    pub(crate) t_end: f64,
    pub(crate) dt0: f64,
    pub(crate) dt_max: f64,
    pub(crate) growth: f64,
    pub(crate) land_on: Vec<f64>,
    pub(crate) kinks: Vec<f64>,
    /// (until, dt_max): a smaller largest step for steps that start before `until` (the
    /// loading ramp's `time.dt_max_ramp`).
    pub(crate) cap: Option<(f64, f64)>,
    /// Error tolerance of the step controller (None: geometric growth).
    pub(crate) tol: Option<f64>,
    /// A step cut below this by failed solves is an error (see `TimeSpec::dt_min`).
    pub(crate) dt_min: f64,
    /// The steps are given (`time.steps`, among the landing times): every step ends at the next
    /// landing time, whatever the growth and the error estimate.
    pub(crate) replay: bool,
}

/// The step controller's limits: a step may grow by at most `MAX_GROWTH` and shrink by at
/// most `MIN_SHRINK`; an estimate above `REJECT` (relative to the tolerance) rejects the step.
const MAX_GROWTH: f64 = 2.0;
const MIN_SHRINK: f64 = 0.2;
const REJECT: f64 = 2.0;

impl Schedule {
    fn eps(&self) -> f64 {
        1e-10 * self.t_end
    }
    /// The next landing time after t.
    fn next_landing(&self, t: f64) -> f64 {
        self.land_on.iter().chain(&self.kinks).copied().filter(|&l| l > t + self.eps()).fold(self.t_end, f64::min)
    }
    /// True if t is one of the kinks.
    pub(crate) fn at_kink(&self, t: f64) -> bool {
        self.kinks.iter().any(|&l| (t - l).abs() <= self.eps())
    }
    /// The step from t with nominal size `nominal`: cut to land on the next landing time, and
    /// stretched by up to 10% instead of leaving a sliver before it.
    pub(crate) fn step(&self, t: f64, nominal: f64) -> f64 {
        let land = self.next_landing(t);
        let gap = land - t;
        if nominal >= gap * (1.0 - 0.1) {
            gap
        } else if nominal > 0.5 * gap {
            0.5 * gap
        } else {
            nominal
        }
    }
    /// Nominal size after a step of nominal size `nominal` that actually took `taken` and ended
    /// at `t`. After landing on a kink of the loading the rate of change jumps: restart from
    /// the first step size and grow again.
    ///
    /// With an error estimate `err` (relative to the tolerance) the next step is the one that
    /// would meet the tolerance, 0.9 dt err^(−1/2) (BE: local error ∝ dt²), within
    /// [MIN_SHRINK, MAX_GROWTH] × dt; it does not shrink below the nominal step while the error
    /// is within tolerance (a step shortened to land on a time is not a sign of trouble).
    pub(crate) fn next_nominal(&self, nominal: f64, taken: f64, t: f64, err: Option<f64>) -> f64 {
        if self.replay {
            return f64::INFINITY;
        }
        if self.at_kink(t) {
            return self.dt0;
        }
        let next = match err {
            Some(e) => {
                let f = (0.9 / e.max(1e-12).sqrt()).clamp(MIN_SHRINK, MAX_GROWTH);
                if f >= 1.0 {
                    (taken * f).max(nominal)
                } else {
                    taken * f
                }
            }
            None => nominal * self.growth,
        };
        next.min(self.dt_max_from(t)).min(2.0 * taken.max(nominal * 1e-3))
    }
    /// The largest step from t.
    fn dt_max_from(&self, t: f64) -> f64 {
        match self.cap {
            Some((until, cap)) if t < until - self.eps() => cap.min(self.dt_max),
            _ => self.dt_max,
        }
    }
    /// Whether an error estimate rejects the step, and the step to retry with.
    pub(crate) fn reject(&self, taken: f64, err: Option<f64>) -> Option<f64> {
        match err.filter(|_| !self.replay) {
            Some(e) if e > REJECT && taken > 1e-3 * self.dt0 => Some(taken * (0.9 / e.sqrt()).max(MIN_SHRINK)),
            _ => None,
        }
    }
    pub(crate) fn done(&self, t: f64) -> bool {
        t >= self.t_end - self.eps()
    }
    /// Steps left from t (no retries), for the ETA.
    pub(crate) fn remaining(&self, mut t: f64, mut nominal: f64) -> usize {
        let mut n = 0;
        while !self.done(t) && n < 1_000_000 {
            let dt = self.step(t, nominal);
            t += dt;
            nominal = self.next_nominal(nominal, dt, t, None);
            n += 1;
        }
        n
    }
}

#[cfg(test)]
mod tests {
    use super::Schedule;

    #[test]
    fn schedule_lands_on_kinks_and_end() {
        let s = Schedule {
            t_end: 10.0,
            dt0: 0.3,
            dt_max: 2.0,
            growth: 1.5,
            land_on: vec![7.7],
            kinks: vec![5.0],
            cap: None,
            tol: None,
            dt_min: 1e-9,
            replay: false,
        };
        let (mut t, mut nom) = (0.0, s.dt0);
        let mut times = vec![];
        while !s.done(t) {
            let dt = s.step(t, nom);
            assert!(dt > 0.0);
            t += dt;
            nom = s.next_nominal(nom, dt, t, None);
            times.push(t);
        }
        assert!(times.iter().any(|&x| (x - 5.0).abs() < 1e-12), "{times:?}");
        // A plain landing time is hit without restarting the growth.
        let j = times.iter().position(|&x| (x - 7.7).abs() < 1e-12).expect("lands on 7.7");
        assert!(times[j + 1] - times[j] > 0.3 + 1e-9, "{times:?}");
        // After the kink the steps restart from dt0.
        let i = times.iter().position(|&x| (x - 5.0).abs() < 1e-12).unwrap();
        assert!((times[i + 1] - times[i] - 0.3).abs() < 1e-12, "{times:?}");
        assert!((t - 10.0).abs() < 1e-12);
        assert!(times.windows(2).all(|w| w[1] - w[0] <= 2.0 * 1.1 + 1e-12));
        assert_eq!(s.remaining(0.0, s.dt0), times.len());
    }

    #[test]
    fn controller_follows_the_error_estimate() {
        let s = Schedule {
            t_end: 100.0,
            dt0: 0.01,
            dt_max: 4.0,
            growth: 1.3,
            land_on: vec![],
            kinks: vec![35.0],
            cap: None,
            tol: Some(1e-3),
            dt_min: 1e-9,
            replay: false,
        };
        // BE: error ∝ dt², so the step meeting the tolerance is 0.9 dt / √err, within [0.2, 2] dt.
        assert!((s.next_nominal(0.1, 0.1, 1.0, Some(0.81)) - 0.1).abs() < 1e-12);
        assert!((s.next_nominal(0.1, 0.1, 1.0, Some(0.09)) - 0.2).abs() < 1e-12);
        assert!((s.next_nominal(0.1, 0.1, 1.0, Some(1e-8)) - 0.2).abs() < 1e-12);
        assert!((s.next_nominal(0.1, 0.1, 1.0, Some(1.8)) - 0.1 * 0.9 / 1.8f64.sqrt()).abs() < 1e-12);
        assert!((s.next_nominal(3.0, 3.0, 1.0, Some(0.01)) - 4.0).abs() < 1e-12, "capped at dt_max");
        // A step shortened to land on a time does not shrink the next one while within tolerance.
        assert!((s.next_nominal(0.5, 0.05, 1.0, Some(0.5)) - 0.5f64.min(0.1)).abs() < 1e-12);
        // No estimate (first step after a kink): geometric growth; on the kink: dt0.
        assert!((s.next_nominal(0.1, 0.1, 1.0, None) - 0.13).abs() < 1e-12);
        assert!((s.next_nominal(0.1, 0.1, 35.0, Some(0.5)) - 0.01).abs() < 1e-12);
        // Rejection above twice the tolerance, retrying with the step that would meet it.
        assert_eq!(s.reject(0.1, Some(1.9)), None);
        assert_eq!(s.reject(0.1, None), None);
        let r = s.reject(0.1, Some(4.0)).expect("rejected");
        assert!((r - 0.045).abs() < 1e-12);
        assert!((s.reject(0.1, Some(1e4)).unwrap() - 0.02).abs() < 1e-12, "at most ×0.2");
    }

    #[test]
    fn the_ramp_cap_holds_until_its_end_only() {
        let s = Schedule {
            t_end: 20.0,
            dt0: 0.02,
            dt_max: 4.0,
            growth: 1.3,
            land_on: vec![],
            kinks: vec![5.0],
            cap: Some((5.0, 0.1)),
            tol: None,
            dt_min: 1e-9,
            replay: false,
        };
        let (mut t, mut nom) = (0.0, s.dt0);
        let mut steps = vec![];
        while !s.done(t) {
            let dt = s.step(t, nom);
            steps.push((t, dt));
            t += dt;
            nom = s.next_nominal(nom, dt, t, None);
        }
        let ramp: Vec<f64> = steps.iter().filter(|(t, _)| *t < 5.0 - 1e-9).map(|&(_, dt)| dt).collect();
        assert!(ramp.iter().all(|&dt| dt <= 0.1 + 1e-12), "{ramp:?}");
        // 0.02 growing by 1.3: 7 steps to the cap (0.35 s), 45 of 0.1 s, the last 0.15 s halved.
        assert_eq!(ramp.len(), 54, "{ramp:?}");
        let after = steps.iter().map(|&(_, dt)| dt).fold(0.0, f64::max);
        assert!(after > 1.0, "the cap ends with the ramp: largest step {after}");
    }

    #[test]
    fn given_steps_are_taken_as_they_are() {
        // As setup builds it from time.steps = [0.1, 0.3, 0.35, 2.0, 7.0] with a kink at 5 s.
        let given = vec![0.1, 0.3, 0.35, 2.0, 7.0];
        let s = Schedule {
            t_end: 10.0,
            dt0: f64::INFINITY,
            dt_max: 1.0,
            growth: 1.3,
            land_on: given.clone(),
            kinks: vec![5.0],
            cap: Some((5.0, 0.1)),
            tol: None,
            dt_min: 1e-9,
            replay: true,
        };
        let (mut t, mut nom) = (0.0, s.dt0);
        let mut times = vec![];
        while !s.done(t) {
            let dt = s.step(t, nom);
            t += dt;
            // Neither an error estimate, the cap, dt_max nor the kink changes the next step.
            nom = s.next_nominal(nom, dt, t, Some(100.0));
            assert_eq!(s.reject(dt, Some(100.0)), None);
            times.push(t);
        }
        // The given times, the kink and the end, exactly.
        assert_eq!(times, [0.1, 0.3, 0.35, 2.0, 5.0, 7.0, 10.0]);
        assert_eq!(s.remaining(0.0, s.dt0), times.len());
        // A step that a failed solve cut short (to 1.0) ends at the next given time.
        assert_eq!(s.step(1.0, nom), 1.0);
    }
}
