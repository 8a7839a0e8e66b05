//! What a [`PoroProblem`](super::PoroProblem) is made of, each part built complete before it
//! (`driver::setup`): the discretisation's parts, the boundary conditions, the surface
//! tension, the medium, the plates, the tools, the drainage and the Schur approximation's matrix.

use crate::fem::dofmap::DofMap;
use crate::fem::element::Tabulation;
use crate::fem::kernel::Stabilisation;
use crate::fem::point::PointModel;
use crate::mesh::dist::LocalMesh;
use crate::petsc::Mat;
use crate::physics::bc::Constraint;
use crate::physics::contact::Plates;
use crate::physics::drainage::SurfaceDrainage;
use crate::physics::medium::Medium;
use crate::physics::surface_tension::SurfaceTension;
use crate::physics::tools::ToolSet;
use crate::reference_cell::shape::MAX_NODES;

/// The parts of a problem.
pub(crate) struct ProblemParts {
    pub(crate) mesh: LocalMesh,
    pub(crate) dofs: DofMap,
    pub(crate) model: Box<dyn PointModel>,
    /// The reference element tabulated at the quadrature points `xi`.
    pub(crate) tab: Tabulation<MAX_NODES>,
    pub(crate) xi: Vec<[f64; 3]>,
    /// The pressure stabilisation the assembly uses.
    pub(crate) stab: Stabilisation,
    /// Equal-order P1–P1 (`fem::equal_order`): the displacement's mid-edge nodes tied to their
    /// edges' vertices, their loads moved there.
    pub(crate) equal_order: bool,
    /// The prescribed dofs this rank's boundary faces found (`bc::build`).
    pub(crate) constraints: Vec<Constraint>,
    /// External loads (traction, prescribed flux) in the local layout, already integrated.
    pub(crate) loads: Vec<f64>,
    /// Surface tension of the boundary, if the scene has it.
    pub(crate) surface: Option<SurfaceTension>,
    /// The medium's pressure on the boundary and in the drained pores, if the scene has it.
    pub(crate) medium: Option<Medium>,
    /// Rigid plates (contact bounds, drainage out of contact), if the scene has them.
    pub(crate) plates: Option<Plates>,
    /// Rigid tools of revolution (exact frictionless contact in their frames), if any.
    pub(crate) tools: Option<ToolSet>,
    /// The surface's drainage off the plates and the sealing tools, if it drains.
    pub(crate) drainage: Option<SurfaceDrainage>,
    /// The fixed-stress Schur approximation's matrix on the pressure space (preallocated).
    pub(crate) schur: Mat,
}
