//! Making per-rank outcomes collective: if any rank fails, every rank returns an error (the
//! failing rank its own, the others the first failure's message), so no rank is left waiting
//! in a collective call while another has returned ([`agree`], and [`agree_ranked`] when the
//! kind of failure matters); whether the ranks passed the same arguments ([`same_on_all`]).
//! Also: work done by rank 0 alone ([`on_root`], [`path_from_root`]), broadcasts, and
//! reductions of scalars and of slices ([`sum_slice`], [`max_slice`], [`reduce_to_root`]), and
//! gathers of slices of any length ([`all_gather_vec`]).

use crate::error::{Error, Result};
use mpi::collective::SystemOperation;
use mpi::datatype::{Equivalence, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

/// All ranks agree on success; on failure the lowest failing rank's message is shared.
pub(crate) fn agree<T>(world: &SimpleCommunicator, local: Result<T>) -> Result<T> {
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

/// [`agree`], and the gravest class of outcome on any rank: `class` ranks an error (≥ 1; a
/// success is 0), so that a caller can tell, e.g., a failure that cuts a time step from one
/// that ends the run, whichever rank it happened on.
pub(crate) fn agree_ranked<T>(
    world: &SimpleCommunicator,
    local: Result<T>,
    class: impl Fn(&Error) -> i32,
) -> (Result<T>, i32) {
    let mine = local.as_ref().err().map_or(0, class);
    let mut worst = 0;
    world.all_reduce_into(&mine, &mut worst, SystemOperation::max());
    (agree(world, local), worst)
}

/// Whether `hash` (of a collective call's arguments, say) is the same on every rank.
pub(crate) fn same_on_all(world: &SimpleCommunicator, hash: u64) -> bool {
    // The maxima of h and of !h are h and !h only if every rank has h.
    let send = [hash, !hash];
    let mut recv = [0u64; 2];
    world.all_reduce_into(&send[..], &mut recv[..], SystemOperation::max());
    recv[0] == hash && !recv[1] == hash
}

/// Runs `f` on rank 0 only, its outcome made collective ([`agree`]): rank 0's value (None on
/// the other ranks), or its error on every rank.
pub(crate) fn on_root<T>(world: &SimpleCommunicator, f: impl FnOnce() -> Result<T>) -> Result<Option<T>> {
    let local = if world.rank() == 0 { f().map(Some) } else { Ok(None) };
    agree(world, local)
}

/// Rank 0's `path` on every rank (the other ranks' is ignored), broadcast as its bytes.
pub(crate) fn broadcast_path(world: &SimpleCommunicator, path: Option<&Path>) -> PathBuf {
    let mut bytes = path.map(|p| p.to_string_lossy().into_owned().into_bytes()).unwrap_or_default();
    broadcast_vec(world, 0, &mut bytes);
    PathBuf::from(String::from_utf8_lossy(&bytes).into_owned())
}

/// The path of a file that rank 0 makes (`f`), on every rank; its error on every rank.
pub(crate) fn path_from_root(world: &SimpleCommunicator, f: impl FnOnce() -> Result<PathBuf>) -> Result<PathBuf> {
    let path = on_root(world, f)?;
    Ok(broadcast_path(world, path.as_deref()))
}

/// Broadcasts a vector of unknown length from `root`.
pub(crate) fn broadcast_vec<T: Equivalence + Default + Clone>(world: &SimpleCommunicator, root: i32, v: &mut Vec<T>) {
    let mut n = v.len() as u64;
    world.process_at_rank(root).broadcast_into(&mut n);
    v.resize(n as usize, T::default());
    if n > 0 {
        world.process_at_rank(root).broadcast_into(&mut v[..]);
    }
}

/// Whether `mine` holds on every rank.
pub(crate) fn all(world: &SimpleCommunicator, mine: bool) -> bool {
    let mut out = 0u8;
    world.all_reduce_into(&u8::from(mine), &mut out, SystemOperation::min());
    out == 1
}

/// Whether `mine` holds on some rank.
pub(crate) fn any(world: &SimpleCommunicator, mine: bool) -> bool {
    let mut out = 0u8;
    world.all_reduce_into(&u8::from(mine), &mut out, SystemOperation::max());
    out == 1
}

/// Sum of a scalar over ranks.
pub(crate) fn sum(world: &SimpleCommunicator, v: f64) -> f64 {
    let mut t = 0.0;
    world.all_reduce_into(&v, &mut t, SystemOperation::sum());
    t
}

/// Maximum of a scalar over ranks.
pub(crate) fn max(world: &SimpleCommunicator, v: f64) -> f64 {
    let mut t = 0.0;
    world.all_reduce_into(&v, &mut t, SystemOperation::max());
    t
}

/// Element-wise sum of `local` over ranks (the same length on every rank).
pub(crate) fn sum_slice<T: Equivalence + Copy + Default>(world: &SimpleCommunicator, local: &[T]) -> Vec<T> {
    let mut out = vec![T::default(); local.len()];
    world.all_reduce_into(local, &mut out[..], SystemOperation::sum());
    out
}

/// Element-wise maximum of `local` over ranks (the same length on every rank).
pub(crate) fn max_slice<T: Equivalence + Copy + Default>(world: &SimpleCommunicator, local: &[T]) -> Vec<T> {
    let mut out = vec![T::default(); local.len()];
    world.all_reduce_into(local, &mut out[..], SystemOperation::max());
    out
}

/// Every rank's `local`, concatenated in rank order, on every rank (the lengths may differ).
pub(crate) fn all_gather_vec<T: Equivalence + Copy + Default>(world: &SimpleCommunicator, local: &[T]) -> Vec<T> {
    let mut counts = vec![0i32; world.size() as usize];
    world.all_gather_into(&(local.len() as i32), &mut counts[..]);
    let displs: Vec<i32> = counts.iter().scan(0, |acc, &c| Some(std::mem::replace(acc, *acc + c))).collect();
    let mut all = vec![T::default(); counts.iter().sum::<i32>() as usize];
    world.all_gather_varcount_into(local, &mut PartitionMut::new(&mut all[..], &counts[..], &displs[..]));
    all
}

/// Element-wise sum over ranks into rank 0's `v` (the other ranks' are left as they were).
pub(crate) fn reduce_to_root(world: &SimpleCommunicator, v: &mut [f64]) {
    let root = world.process_at_rank(0);
    if world.rank() == 0 {
        let mut out = vec![0.0; v.len()];
        root.reduce_into_root(&v[..], &mut out[..], SystemOperation::sum());
        v.copy_from_slice(&out);
    } else {
        root.reduce_into(&v[..], SystemOperation::sum());
    }
}
