//! Making per-rank outcomes collective: if any rank fails, every rank returns an error (the
//! failing rank its own, the others the first failure's message), so no rank is left waiting
//! in a collective call while another has returned. Also: work done by rank 0 alone
//! ([`on_root`], [`path_from_root`]), broadcasts and reductions of small values.

use crate::error::{Error, Result};
use mpi::collective::SystemOperation;
use mpi::datatype::Equivalence;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

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

/// Runs `f` on rank 0 only, its outcome made collective ([`agree`]): rank 0's value (None on
/// the other ranks), or its error on every rank.
pub fn on_root<T>(world: &SimpleCommunicator, f: impl FnOnce() -> Result<T>) -> Result<Option<T>> {
    let local = if world.rank() == 0 { f().map(Some) } else { Ok(None) };
    agree(world, local)
}

/// Rank 0's `path` on every rank (the other ranks' is ignored), broadcast as its bytes.
pub fn broadcast_path(world: &SimpleCommunicator, path: Option<&Path>) -> PathBuf {
    let mut bytes = path.map(|p| p.to_string_lossy().into_owned().into_bytes()).unwrap_or_default();
    broadcast_vec(world, 0, &mut bytes);
    PathBuf::from(String::from_utf8_lossy(&bytes).into_owned())
}

/// The path of a file that rank 0 makes (`f`), on every rank; its error on every rank.
pub fn path_from_root(world: &SimpleCommunicator, f: impl FnOnce() -> Result<PathBuf>) -> Result<PathBuf> {
    let path = on_root(world, f)?;
    Ok(broadcast_path(world, path.as_deref()))
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
