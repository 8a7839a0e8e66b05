//! The one element loop over the local cells, for both cell families: gathers each element's
//! coordinates, nodal values and qp state, calls the family's kernel (`fem::kernel`, through
//! [`CellKernel`]) and scatters the result. Residual, Jacobian, qp-state commit, post-processing
//! and the compaction check are bodies of this loop.

use super::cell::{CellShape, Tet10, Tri6Axi};
use super::dofmap::DofMap;
use super::element::{ElementDofs, ElementMatrix, Tabulation, MAX_DOF};
use super::kernel::{CellKernel, ElementInput, ElementKernel, ElementValues, Stabilisation};
use super::point::{PointModel, QpState};
use super::qp_store::QpStore;
use crate::error::Result;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{Int, Mat};
use crate::reference_cell::shape::{MAX_NODES, MAX_VERTICES};
use crate::reference_cell::Family;
use std::marker::PhantomData;

/// What the element loops read: mesh, dofs, model, quadrature, constraint flags.
pub(crate) struct Discretization {
    pub(crate) mesh: LocalMesh,
    pub(crate) dofs: DofMap,
    pub(crate) model: Box<dyn PointModel>,
    /// Cell functions at the quadrature points (`element::tabulate_cell`).
    pub(crate) tab: Tabulation<MAX_NODES>,
    pub(crate) xi: Vec<[f64; 3]>,
    /// Per local dof: fixed by a constraint.
    pub(crate) constrained: Vec<bool>,
    /// The pressure stabilisation (see `fem::kernel::ElementKernel::stab`).
    pub(crate) stab: Stabilisation,
    /// Committed qp state of the model (empty when it has none).
    pub(crate) qp_state: QpStore,
    /// Equal-order P1–P1 instead of Taylor–Hood (`fem::equal_order`; tetrahedra only).
    pub(crate) equal_order: bool,
    /// Whether the qp state evolves in the steps being solved (false while settling before t = 0,
    /// where B_p(X, 0⁻) = I holds by definition).
    pub(crate) evolve: bool,
}

/// Whose qp state an element sees.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum QpStateUse {
    /// The step being solved: evolves from the committed state (unless `evolve` is off).
    Step,
    /// Held at the committed state (post-processing of a committed step).
    Held,
}

impl Discretization {
    pub(crate) fn family(&self) -> Family {
        self.mesh.family
    }

    /// Dofs of an element.
    pub(crate) fn ndof(&self) -> usize {
        let f = self.family();
        f.components() * f.cell_nodes() + f.cell_vertices()
    }

    /// The kernel of the mesh's cell family.
    pub(crate) fn kernel(&self) -> Box<dyn CellKernel + '_> {
        fn make<'a, C: CellShape>(d: &'a Discretization) -> Box<dyn CellKernel + 'a> {
            Box::new(ElementKernel::<C> {
                model: d.model.as_ref(),
                tab: &d.tab,
                xi: &d.xi,
                stab: d.stab,
                equal_order: d.equal_order,
                family: PhantomData,
            })
        }
        match self.family() {
            Family::Tet10 => make::<Tet10>(self),
            Family::Tri6 => make::<Tri6Axi>(self),
        }
    }

    /// The one element loop: element e's local dofs and kernel input at the local state (u, u̇)
    /// of a step of size dt go to `body`; an error names the cell of the file (the input's
    /// `elem`, which the model puts in its domain errors).
    pub(crate) fn each_element(
        &self,
        u: &[f64],
        udot: &[f64],
        dt: f64,
        qp_state: QpStateUse,
        mut body: impl FnMut(usize, &ElementDofs, &ElementInput) -> Result<()>,
    ) -> Result<()> {
        let evolve = self.evolve && qp_state == QpStateUse::Step;
        for e in 0..self.mesh.cells.len() {
            let d = self.element_dofs(e);
            let h = QpState { committed: self.qp_state.element(e), evolve };
            let input = self.gather(e, &d, u, udot, dt, h);
            body(e, &d, &input)?;
        }
        Ok(())
    }

    /// Adds the element residuals at (u, u̇) into `f` (local layout).
    pub(crate) fn add_residual(&self, u: &[f64], udot: &[f64], dt: f64, f: &mut [f64]) -> Result<()> {
        let (kernel, n) = (self.kernel(), self.ndof());
        self.each_element(u, udot, dt, QpStateUse::Step, |_, d, input| {
            let mut r = [0.0; MAX_DOF];
            kernel.residual(input, &mut r)?;
            for k in 0..n {
                f[d[k]] += r[k];
            }
            Ok(())
        })
    }

    /// Element loop of the Jacobian: element matrices (constrained rows and columns zeroed,
    /// so the pattern stays fixed) go to `sink`, Schur blocks into `schur` if given.
    pub(crate) fn jacobian_loop(
        &self,
        ul: &[f64],
        udl: &[f64],
        dt: f64,
        shift: f64,
        mut schur: Option<&mut Mat>,
        mut sink: impl FnMut(usize, &ElementDofs, &ElementMatrix) -> Result<()>,
    ) -> Result<()> {
        let (kernel, n, nv) = (self.kernel(), self.ndof(), self.family().cell_vertices());
        let nu = n - nv;
        let mut k = Box::new([[0.0; MAX_DOF]; MAX_DOF]);
        let mut prows = [0 as Int; MAX_VERTICES];
        self.each_element(ul, udl, dt, QpStateUse::Step, |e, d, input| {
            for row in k.iter_mut().take(n) {
                *row = [0.0; MAX_DOF];
            }
            let mut s = [[0.0; MAX_VERTICES]; MAX_VERTICES];
            kernel.jacobian(input, shift, &mut k, &mut s)?;
            for a in 0..n {
                if self.constrained[d[a]] {
                    k[a] = [0.0; MAX_DOF];
                    for row in k.iter_mut().take(n) {
                        row[a] = 0.0;
                    }
                }
            }
            sink(e, d, &k)?;
            let cell = &self.mesh.cells[e];
            for m in 0..nv {
                let lv = self.mesh.vertex_of_node[cell[m] as usize] as usize;
                prows[m] = self.mesh.vertex_global[lv] as Int;
                if self.constrained[d[nu + m]] {
                    s[m] = [0.0; MAX_VERTICES];
                    for row in s.iter_mut() {
                        row[m] = 0.0;
                    }
                }
            }
            if let Some(sm) = schur.as_deref_mut() {
                let block: Vec<f64> = s[..nv].iter().flat_map(|row| row[..nv].iter().copied()).collect();
                sm.add_values(&prows[..nv], &prows[..nv], &block)?;
            }
            Ok(())
        })
    }

    /// The end-of-step qp state of every point at the accepted state (u, u̇) of a step of size dt.
    pub(crate) fn advanced_qp_state(&self, u: &[f64], udot: &[f64], dt: f64) -> Result<QpStore> {
        let kernel = self.kernel();
        let mut next = self.qp_state.clone();
        self.each_element(u, udot, dt, QpStateUse::Step, |e, _, input| {
            kernel.advance_qp_state(input, next.element_mut(e))
        })?;
        Ok(next)
    }

    /// The smallest J = det F over this rank's points in the state `u`.
    pub(crate) fn min_j(&self, u: &[f64]) -> Result<f64> {
        let kernel = self.kernel();
        let mut m = f64::INFINITY;
        self.each_element(u, u, 1.0, QpStateUse::Step, |_, _, input| {
            m = m.min(kernel.min_j(input)?);
            Ok(())
        })?;
        Ok(m)
    }

    /// Local dof indices of element e in kernel order (the first `ndof()` entries).
    #[inline]
    pub(crate) fn element_dofs(&self, e: usize) -> ElementDofs {
        self.dofs.element_dofs(&self.mesh, e)
    }

    /// The kernel's input for element e: coordinates, values of U and U̇, step size, qp state.
    fn gather<'h>(
        &self,
        e: usize,
        dofs: &ElementDofs,
        u: &[f64],
        udot: &[f64],
        dt: f64,
        qp_state: QpState<'h>,
    ) -> ElementInput<'h> {
        let f = self.family();
        let (nn, nv, nc) = (f.cell_nodes(), f.cell_vertices(), f.components());
        let t = &self.mesh.cells[e];
        let mut coords = [[0.0; 3]; MAX_NODES];
        let mut v = ElementValues {
            u: [[0.0; 3]; MAX_NODES],
            udot: [[0.0; 3]; MAX_NODES],
            p: [0.0; MAX_VERTICES],
            pdot: [0.0; MAX_VERTICES],
        };
        for a in 0..nn {
            coords[a] = self.mesh.coords[t[a] as usize];
            for c in 0..nc {
                v.u[a][c] = u[dofs[nc * a + c]];
                v.udot[a][c] = udot[dofs[nc * a + c]];
            }
        }
        for m in 0..nv {
            v.p[m] = u[dofs[nc * nn + m]];
            v.pdot[m] = udot[dofs[nc * nn + m]];
        }
        ElementInput { elem: self.mesh.cell_original[e] as usize, coords, values: v, dt, qp_state }
    }
}
