//! The upper plate of a scene with force rows in `plates.upper`, one `history.csv` row per
//! step: where it is (under force control, the creep) and the force prescribed on it.

use crate::io::recorder::Declared;
use crate::physics::contact::Plates;
use crate::physics::tools::protocol::Mode;

/// The `history.csv` columns of an [`UpperPlate`] (with force rows in `plates.upper`).
pub(crate) const COLUMNS: [Declared<UpperPlate>; 2] = [
    Declared::real(
        "upper_plate_disp",
        "µm",
        "displacement of the upper plate downwards from z = 2R (with force rows in plates.upper; under force \
         control an unknown: the creep)",
        |u| u.disp,
    ),
    Declared::real(
        "force_target_uN",
        "µN",
        "the force prescribed on the upper plate by plates.upper, full-body equivalent (nan under displacement \
         control; compare force_total_uN)",
        |u| u.target,
    ),
];

/// The upper plate at a step's end.
pub(crate) struct UpperPlate {
    disp: f64,
    target: f64,
}

/// The upper plate of `plates` at time t, at displacement d (the state's, `Post::upper_d`).
pub(crate) fn observe(plates: &Plates, t: f64, d: f64) -> UpperPlate {
    let target = match plates.upper.at(t, 0.0) {
        Mode::Force(f) => f * 1e-3,
        Mode::Displacement(_) => f64::NAN,
    };
    UpperPlate { disp: d, target }
}
