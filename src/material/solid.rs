//! The mixture's solid (model.md (39)): a skeleton law plus the optional compaction penalty,
//! evaluated as one [`SolidLaw`].

use super::law::{Kinematics, SkeletonLaw, SolidLaw, SolidResponse};
use super::penalty::CompactionPenalty;
use crate::error::Result;
use nalgebra::Matrix3;

/// The mixture's solid: a skeleton law plus, if given, the compaction penalty (model.md (39) in
/// full).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Solid<'a, L> {
    pub(crate) law: &'a L,
    pub(crate) penalty: Option<&'a CompactionPenalty>,
}

impl<L: SkeletonLaw> SolidLaw for Solid<'_, L> {
    fn energy(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<f64> {
        let mut psi = self.law.energy(kin, bp)?;
        if let Some(pen) = self.penalty {
            psi += pen.energy(kin, bp)?;
        }
        Ok(psi)
    }

    fn stresses(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)> {
        let (mut p, mut s) = self.law.stresses(kin, bp)?;
        if let Some(pen) = self.penalty {
            let (pp, ps) = pen.stresses(kin, bp)?;
            p += pp;
            s += ps;
        }
        Ok((p, s))
    }

    fn response(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<SolidResponse> {
        let mut r = self.law.response(kin, bp)?;
        if let Some(pen) = self.penalty {
            let u = pen.response(kin, bp)?;
            r.p += u.p;
            r.a += u.a;
            r.s += u.s;
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::super::laws::HolmesMow;
    use super::super::test_util::{kin, rel_err, Rng};
    use super::*;

    /// The solid is the sum of its parts, and Holmes–Mow alone without the penalty.
    #[test]
    fn combined_response_is_the_sum_of_its_parts() {
        let hm = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        let (with, alone) = (Solid { law: &hm, penalty: Some(&pen) }, Solid { law: &hm, penalty: None });
        let mut rng = Rng::new(22);
        for j in [0.63, 0.68, 0.9] {
            let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
            let k = kin(&f);
            let r = with.response(&k, &bp).unwrap();
            let (s_hm, s_pen) = (hm.stresses(&k, &bp).unwrap().1, pen.stresses(&k, &bp).unwrap().1);
            assert!(rel_err(&r.s, &(s_hm + s_pen)) < 1e-14);
            let psi = hm.energy(&k, &bp).unwrap() + pen.energy(&k, &bp).unwrap();
            assert_eq!(with.energy(&k, &bp).unwrap(), psi);
            assert_eq!(alone.response(&k, &bp).unwrap(), hm.response(&k, &bp).unwrap());
            assert_eq!(alone.stresses(&k, &bp).unwrap(), hm.stresses(&k, &bp).unwrap());
        }
    }

    #[test]
    fn combined_response_is_frame_invariant() {
        let hm = HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap();
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        let mut rng = Rng::new(23);
        let (f, bp, q) = (rng.deformation(0.65), rng.remodelling_metric(), rng.rotation());
        let solid = Solid { law: &hm, penalty: Some(&pen) };
        let r = solid.response(&kin(&f), &bp).unwrap();
        let rq = solid.response(&kin(&(q * f)), &bp).unwrap();
        assert!(rel_err(&rq.p, &(q * r.p)) < 1e-13);
        assert!(rel_err(&rq.s, &r.s) < 1e-13);
    }
}
