//! Orthonormal bases of distributed vectors (the rigid-body modes).

use crate::error::Result;
use crate::petsc::Vector;

/// Modified Gram–Schmidt with global dot products.
pub(super) fn orthonormalise(vs: &mut [Vector]) -> Result<()> {
    for i in 0..vs.len() {
        let (done, rest) = vs.split_at_mut(i);
        let v = &mut rest[0];
        for q in done.iter() {
            let d = v.dot(q)?;
            v.axpy(-d, q)?;
        }
        let n = v.norm2()?;
        if n > 0.0 {
            v.scale(1.0 / n)?;
        }
    }
    Ok(())
}
