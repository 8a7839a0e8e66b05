//! `-log_view` stages.

use super::{check, ffi};
use crate::error::Result;
use std::ffi::CString;

/// A `-log_view` stage, entered for the lifetime of the guard from [`Stage::push`].
#[derive(Clone, Copy)]
pub(crate) struct Stage(ffi::PetscLogStage);

impl Stage {
    /// Registers a named stage.
    pub(crate) fn register(name: &str) -> Result<Stage> {
        let n = CString::new(name).unwrap_or_default();
        let mut s: ffi::PetscLogStage = 0;
        check(unsafe { ffi::PetscLogStageRegister(n.as_ptr(), &mut s) })?;
        Ok(Stage(s))
    }
    /// Enters the stage until the guard drops.
    pub(crate) fn push(self) -> StageGuard {
        unsafe { ffi::PetscLogStagePush(self.0) };
        StageGuard
    }
}

/// Leaves the log stage on drop.
pub(crate) struct StageGuard;
impl Drop for StageGuard {
    fn drop(&mut self) {
        unsafe { ffi::PetscLogStagePop() };
    }
}
