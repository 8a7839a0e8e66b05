//! States outside a law's domain, and where they happen: the material code does not know the
//! element and quadrature point it is evaluated at, so its errors carry 0 there and the caller
//! fills them in.

use crate::error::{Error, Result};

/// A state outside a law's domain. The material code does not know where it is evaluated, so
/// cell and point are 0; the caller fills them in with [`locate`] or [`AtPoint::at_point`].
pub(crate) fn domain_error(j: f64, msg: impl Into<String>) -> Error {
    Error::Domain { cell: 0, point: 0, j, msg: msg.into() }
}

/// Puts the element and quadrature point into a [`Error::Domain`]; other errors pass unchanged.
pub(crate) fn locate(err: Error, cell: usize, point: usize) -> Error {
    match err {
        Error::Domain { j, msg, .. } => Error::Domain { cell, point, j, msg },
        other => other,
    }
}

/// `material_call(..).at_point(cell, q)?` fills in where a domain error happened.
pub(crate) trait AtPoint {
    fn at_point(self, cell: usize, point: usize) -> Self;
}

impl<T> AtPoint for Result<T> {
    fn at_point(self, cell: usize, point: usize) -> Self {
        self.map_err(|e| locate(e, cell, point))
    }
}

/// Φs must lie in (0, 1); shared by all laws.
pub(crate) fn check_phi_s(law: &str, phi_s: f64) -> Result<()> {
    if phi_s > 0.0 && phi_s < 1.0 {
        Ok(())
    } else {
        Err(Error::Material(format!("{law}: solid fraction phi_s = {phi_s} outside (0, 1)")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caller_fills_in_location() {
        let r: Result<()> = Err(domain_error(-0.5, "J <= 0"));
        match r.at_point(12, 3) {
            Err(Error::Domain { cell: 12, point: 3, j, msg }) => {
                assert!(j == -0.5 && msg == "J <= 0")
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(locate(Error::Material("x".into()), 1, 2), Error::Material(_)));
    }
}
