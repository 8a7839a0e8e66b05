//! Making per-rank outcomes collective: if any rank fails, every rank returns an error (the
//! failing rank its own, the others the first failure's message), so no rank is left waiting
//! in a collective call while another has returned.

use crate::error::{Error, Result};
use mpi::collective::SystemOperation;
use mpi::datatype::Equivalence;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// All ranks agree on success; on failure the lowest failing rank's message is shared.
pub fn agree<T>(world: &SimpleCommunicator, local: Result<T>) -> Result<T> {
    let me = if local.is_err() { world.rank() } else { world.size() };
    let mut first = 0;
    world.all_reduce_into(&me, &mut first, SystemOperation::min());
    if first == world.size() {
        return local;
    }
    let mut msg = match &local {
        Err(e) if world.rank() == first => e.to_string().into_bytes(),
        _ => Vec::new(),
    };
    broadcast_vec(world, first, &mut msg);
    match local {
        Err(e) => Err(e),
        Ok(_) => Err(Error::Elsewhere { rank: first, msg: String::from_utf8_lossy(&msg).into_owned() }),
    }
}

/// Broadcasts a vector of unknown length from `root`.
pub fn broadcast_vec<T: Equivalence + Default + Clone>(world: &SimpleCommunicator, root: i32, v: &mut Vec<T>) {
    let mut n = v.len() as u64;
    world.process_at_rank(root).broadcast_into(&mut n);
    v.resize(n as usize, T::default());
    if n > 0 {
        world.process_at_rank(root).broadcast_into(&mut v[..]);
    }
}

/// Whether `mine` holds on every rank.
pub fn all(world: &SimpleCommunicator, mine: bool) -> bool {
    let mut out = 0u8;
    world.all_reduce_into(&u8::from(mine), &mut out, SystemOperation::min());
    out == 1
}

/// Whether `mine` holds on some rank.
pub fn any(world: &SimpleCommunicator, mine: bool) -> bool {
    let mut out = 0u8;
    world.all_reduce_into(&u8::from(mine), &mut out, SystemOperation::max());
    out == 1
}

/// Sum of a scalar over ranks.
pub fn sum(world: &SimpleCommunicator, v: f64) -> f64 {
    let mut t = 0.0;
    world.all_reduce_into(&v, &mut t, SystemOperation::sum());
    t
}

/// Maximum of a scalar over ranks.
pub fn max(world: &SimpleCommunicator, v: f64) -> f64 {
    let mut t = 0.0;
    world.all_reduce_into(&v, &mut t, SystemOperation::max());
    t
}
