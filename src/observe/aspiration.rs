//! What a lab reads of a micropipette aspiration (issue 53, design §7): the aspirated length
//! L — how far the tongue's tip has entered the pipette, L = max(0, −ζ_tip) with ζ_tip the
//! smallest height along the pipette's axis (its frame: ζ < 0 inside) of the wetted surface's
//! nodes within the bore (ρ < Rp): on the meridian the node on the axis facing the pipette
//! (the tongue's tip) — and the medium's drag on the body, which must stay far below the
//! suction's force when the drag only regularises the released body's translation.

use crate::fem::dofmap::DofMap;
use crate::io::recorder::Declared;
use crate::mesh::dist::LocalMesh;
use crate::parallel::{max, sum};
use crate::physics::medium::Medium;
use crate::scene::medium::MediumSpec;
use mpi::topology::SimpleCommunicator;

/// The aspiration's values at a step's end.
pub(crate) struct Aspiration {
    length: f64,
}

/// The medium's drag at a step's end.
pub(crate) struct MediumDrag {
    along_z: f64,
}

/// With a `[[medium.suction]]`.
pub(crate) const LENGTH: [Declared<Aspiration>; 1] = [Declared::real(
    "aspirated_length",
    "µm",
    "how far the surface has entered the (first) sucking pipette: the largest depth −ζ beyond its mouth of a \
     wetted surface node within its bore (ρ < R_p; on the meridian the tongue's tip on the axis), 0 when none",
    |a| a.length,
)];

/// With a `[medium]` of non-zero viscosity.
pub(crate) const DRAG: [Declared<MediumDrag>; 1] = [Declared::real(
    "drag_uN",
    "µN",
    "the medium's viscous drag on the body along z (the meridian's axis), ζ_d ∫ u̇_z da with ζ_d = 3η_m/(2R₀), \
     positive resisting motion towards −z, full body on the meridian",
    |d| d.along_z,
)];

/// Which of the two columns a scene's `[medium]` writes: (aspirated length, drag).
pub(crate) fn columns(medium: Option<&MediumSpec>) -> (bool, bool) {
    medium.map_or((false, false), |m| (!m.suction.is_empty(), m.viscosity > 0.0))
}

/// The aspirated length in the first suction's pipette (collective; 0 without a suction).
pub(crate) fn aspiration(
    medium: &Medium,
    mesh: &LocalMesh,
    dofs: &DofMap,
    local: &[f64],
    world: &SimpleCommunicator,
) -> Aspiration {
    let mut depth = 0.0f64;
    if let Some(s) = medium.suctions().first() {
        let rp = s.inner_radius();
        let nn = mesh.family.face_nodes();
        for &f in medium.faces() {
            for &n in &mesh.face(f as usize)[..nn] {
                let n = n as usize;
                let mut x = [0.0; 3];
                for (c, &axis) in mesh.family.axes().iter().enumerate() {
                    x[c] = mesh.coords[n][axis] + local[dofs.u_local(n, c)];
                }
                let (rho, zeta) = s.frame(&x, medium.meridian());
                if rho < rp {
                    depth = depth.max(-zeta);
                }
            }
        }
    }
    Aspiration { length: max(world, depth) }
}

/// The drag's total along z from each rank's share (`Post::drag`, nN) (collective), µN.
pub(crate) fn drag(local: [f64; 3], meridian: bool, world: &SimpleCommunicator) -> MediumDrag {
    // The residual's share is the body's pull on the medium: the drag on the body is its opposite.
    let z = if meridian { local[1] } else { local[2] };
    MediumDrag { along_z: -1e-3 * sum(world, z) }
}
