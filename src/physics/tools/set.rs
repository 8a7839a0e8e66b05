//! The tools of a scene and the body's surface that can touch them, as the active-set Newton
//! sees them at each iterate ([`CurvedContact`]): for every candidate node (a node of the
//! contact surface, owned or ghost) its nearest tool, the gap φ there, and — within a band of
//! the tool — the frame whose last axis is the tool's normal ∇φ, with ∇²φ for the contact's
//! curvature. The frames are recomputed from the iterate in every residual evaluation (the bound
//! is re-linearised at each iterate: issue 53's design, §3.2), after the ghost exchange, so every
//! rank computes a shared node's frame from the same bits.
//!
//! Exact contact at the nodes: an iterate is projected onto the tools (a node inside one is moved
//! to its closest surface point), as the bounds' clamp does for the plates; the split then moves
//! an active node onto the linearised tool, −σφ along its normal, which is round-off after the
//! projection.

use super::protocol::{untouched, Mode, Progress, ToolProtocol};
use super::tool::Tool;
use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::parallel::all_gather_vec;
use crate::petsc::{Int, Vector};
use crate::solver::active_set::{
    CurvedContact, Frame, Moves, NodeContact, PositionUnknown, Positions, SharedPositions,
};
use mpi::topology::SimpleCommunicator;
use mpi::traits::Communicator;

/// A force-controlled tool touches the body at a switch if a node is within this fraction of
/// the frame band (two mean cell sizes) of it; a smaller gap is closed by the solver's contact
/// search.
const TOUCH: f64 = 0.01;

/// A candidate node of the contact surface.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    /// Local node (owned if below the dof map's `n_owned_nodes`).
    node: usize,
    /// Its reference position in space (the meridian's (r, 0, z)).
    x_ref: [f64; 3],
    /// Its prescribed components (in the node's components): a symmetry plane's, or the
    /// meridian's axis. The tool's normal there lies in the plane (a tool of the symmetric
    /// scene is its own mirror image), so the frame keeps them as their own axes.
    held: [bool; 3],
}

/// The nearest tool of a candidate in a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Nearest {
    pub(crate) tool: usize,
    pub(crate) phi: f64,
}

/// The scene's tools, their protocols and the surface that can touch them.
pub(crate) struct ToolSet {
    tools: Vec<Tool>,
    /// Each tool's protocol (displacement or force along its axis against time), and where it
    /// stands between steps.
    protocols: Vec<ToolProtocol>,
    progress: Vec<Progress>,
    /// The tools' positions at the iterate being solved (and their targets under force
    /// control), shared with the solver, which moves a force-controlled one.
    positions: SharedPositions,
    /// Displacement components per node: 2 on the meridian (r, z), else 3.
    nc: usize,
    candidates: Vec<Candidate>,
    /// The first global u dof of every candidate of every rank, ascending: a node's frame
    /// rotates its columns on every rank whose rows couple to it, which may not hold the node
    /// at all (its rows gather other ranks' cells), so every rank keeps every frame.
    global_first: Vec<Int>,
    world: SimpleCommunicator,
    n_owned_nodes: usize,
    /// Candidates within this gap of a tool get a frame (µm).
    band: f64,
    /// At the iterate last evaluated: the frame of each candidate of `global_first`; the owned
    /// framed nodes.
    frames: Vec<Option<Frame>>,
    nodes: Vec<NodeContact>,
}

impl ToolSet {
    /// The tools with their protocols, touching the nodes of the `faces` (this rank's; their vertices
    /// only with `on_vertices`, as for the plates under P1–P1), except nodes with a prescribed
    /// displacement along z (a frame would mix its constraint row with the others), or in r off
    /// the meridian's axis, and the `pinned` local nodes
    /// (held by bounds: the plates' anchor). `band`: the gap within which a node gets a frame.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        world: &SimpleCommunicator,
        tools: Vec<Tool>,
        protocols: Vec<ToolProtocol>,
        mesh: &LocalMesh,
        dofs: &DofMap,
        faces: &[u32],
        on_vertices: bool,
        constrained: &[bool],
        pinned: &[usize],
        band: f64,
    ) -> ToolSet {
        let per_face = if on_vertices { mesh.family.face_vertices() } else { mesh.family.face_nodes() };
        let mut nodes: Vec<usize> =
            faces.iter().flat_map(|&f| mesh.face(f as usize)[..per_face].iter().map(|&n| n as usize)).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let nc = dofs.nc;
        let meridian = nc == 2;
        let held_in = |n: usize, c: usize| constrained[dofs.u_local(n, c)];
        let on_axis = |n: usize| meridian && mesh.coords[n][0] == 0.0;
        // Nodes held in x or y (3-D symmetry planes) or in r on the axis keep a frame: the tools'
        // normal has no component there, and the rotation taking e_z to a normal with n_c = 0
        // keeps e_c as an axis exactly (`Frame::spatial`), so their constraint rows stay apart.
        let held = |n: usize| held_in(n, nc - 1) || (meridian && held_in(n, 0) && !on_axis(n));
        // A node's frame rotates its rows (on its owner) and its columns (on every rank whose rows
        // couple to it): every rank must agree on the candidates, also where it holds a node only
        // through a cell whose surface face it does not hold. So the set is the union over ranks
        // (by global node), less every node held on some rank.
        let global = |ns: &mut dyn Iterator<Item = usize>| -> Vec<u32> {
            let mut g = all_gather_vec(world, &ns.map(|n| mesh.node_global[n]).collect::<Vec<u32>>());
            g.sort_unstable();
            g.dedup();
            g
        };
        let on_surface = global(&mut nodes.iter().copied());
        let excluded =
            global(&mut nodes.iter().copied().filter(|&n| held(n) && !on_axis(n)).chain(pinned.iter().copied()));
        let nodes: Vec<usize> = (0..mesh.coords.len())
            .filter(|&n| {
                let g = mesh.node_global[n];
                on_surface.binary_search(&g).is_ok() && excluded.binary_search(&g).is_err()
            })
            .collect();
        let candidates: Vec<Candidate> = nodes
            .iter()
            .map(|&n| Candidate {
                node: n,
                x_ref: mesh.coords[n],
                held: std::array::from_fn(|c| c < nc && held_in(n, c)),
            })
            .collect();
        let owned_first: Vec<Int> =
            nodes.iter().filter(|&&n| n < dofs.n_owned_nodes).map(|&n| dofs.l2g[dofs.u_local(n, 0)]).collect();
        let mut global_first = all_gather_vec(world, &owned_first);
        global_first.sort_unstable();
        let progress: Vec<Progress> = protocols.iter().map(Progress::start).collect();
        let positions = Positions { d: progress.iter().map(|p| p.d).collect(), target: vec![None; tools.len()] };
        let k = global_first.len();
        ToolSet {
            tools,
            protocols,
            progress,
            positions: std::rc::Rc::new(std::cell::RefCell::new(positions)),
            nc,
            candidates,
            global_first,
            world: world.duplicate(),
            n_owned_nodes: dofs.n_owned_nodes,
            band,
            frames: vec![None; k],
            nodes: Vec::new(),
        }
    }

    pub(crate) fn tools(&self) -> &[Tool] {
        &self.tools
    }

    /// The gap within which a node gets a frame (µm).
    pub(crate) fn band(&self) -> f64 {
        self.band
    }

    /// The tools' positions along their axes now (the last iterate's: the solution's after a
    /// step).
    pub(crate) fn positions(&self) -> Vec<f64> {
        self.positions.borrow().d.clone()
    }

    /// The kinks of the tools' protocols (steps land on them).
    pub(crate) fn kinks(&self) -> Vec<f64> {
        self.protocols.iter().flat_map(ToolProtocol::kinks).collect()
    }

    /// Moves the tools to the stage time t of the step from `start`: a displacement-controlled
    /// tool where its protocol puts it; a force-controlled one at its committed position (plus
    /// its last rate's advance with `extrapolate`), from which the solver moves it, with its
    /// target (nN; on a mirrored 3-D mesh the meshed part's, as the tools' force columns).
    pub(crate) fn stage(&mut self, start: f64, t: f64, extrapolate: bool) {
        let mut positions = self.positions.borrow_mut();
        for (k, (progress, protocol)) in self.progress.iter_mut().zip(&self.protocols).enumerate() {
            let (d, force) = progress.stage(protocol, start, t, extrapolate);
            positions.d[k] = d;
            positions.target[k] = force;
        }
    }

    /// Commits the positions of the accepted step of size dt (their rates kept with
    /// `keep_rate`).
    pub(crate) fn commit(&mut self, dt: f64, keep_rate: bool) {
        let positions = self.positions.borrow();
        for (p, &d) in self.progress.iter_mut().zip(&positions.d) {
            p.commit(d, dt, keep_rate);
        }
    }

    /// The tools between steps (for a checkpoint).
    pub(crate) fn progress(&self) -> &[Progress] {
        &self.progress
    }

    /// Restores the tools of a checkpoint at time t: tool k from `saved[k]`, or where its
    /// protocol puts it at t if the checkpoint has none (one written before tools had a state).
    pub(crate) fn set_progress(&mut self, saved: &[Progress], t: f64) {
        let mut positions = self.positions.borrow_mut();
        for (k, p) in self.progress.iter_mut().enumerate() {
            *p = saved.get(k).copied().unwrap_or_else(|| Progress::from_table(&self.protocols[k], t));
            positions.d[k] = p.d;
        }
    }

    /// The force-controlled tools as positions of the solver's border (tools with force rows).
    pub(crate) fn border_unknowns(&self) -> Vec<PositionUnknown> {
        (0..self.tools.len())
            .filter(|&k| self.protocols[k].has_force())
            .map(|k| PositionUnknown {
                shared: self.positions.clone(),
                index: k,
                name: format!("tool \"{}\"", self.tools[k].name),
                moves: Moves::Tool(k),
            })
            .collect()
    }

    /// At the first stage after a switch to force control (or the first of a run under it):
    /// every such tool must touch the body at the step's start `x0` (owned entries; `t` the
    /// switch's time), else the error says what to do (collective).
    pub(crate) fn check_touch(&self, x0: &[f64], t: f64) -> Result<()> {
        let targets = self.positions.borrow().target.clone();
        self.refuse_untouched(x0, t, |k| targets[k].is_some() && self.progress[k].switched)
    }

    /// At setup: every tool under force control from t = 0 must touch the body.
    pub(crate) fn check_start(&self, x0: &[f64]) -> Result<()> {
        let from_start = |k: usize| matches!(self.protocols[k].at(f64::MIN_POSITIVE, 0.0), Mode::Force(_));
        self.refuse_untouched(x0, 0.0, from_start)
    }

    /// The tools `which` must have a node of `x0` (owned entries) within `TOUCH` of them, at
    /// their committed positions (collective).
    fn refuse_untouched(&self, x0: &[f64], t: f64, which: impl Fn(usize) -> bool) -> Result<()> {
        let committed: Vec<f64> = self.progress.iter().map(|p| p.d).collect();
        let mut far = vec![f64::NEG_INFINITY; self.tools.len()];
        for (_, _, near) in self.owned_gaps(x0, &committed) {
            far[near.tool] = far[near.tool].max(-near.phi);
        }
        let far = crate::parallel::max_slice(&self.world, &far);
        for (k, tool) in self.tools.iter().enumerate() {
            if which(k) && -far[k] > TOUCH * self.band {
                return Err(Error::Scene {
                    path: format!("[[tools]] \"{}\": tools.protocol", tool.name),
                    msg: untouched(&format!("tool \"{}\"", tool.name), t, -far[k]),
                });
            }
        }
        Ok(())
    }

    /// The current position of candidate i in the local state `u` (the meridian's (r, 0, z)).
    fn position_of(&self, i: usize, u: &[f64]) -> [f64; 3] {
        let c = &self.candidates[i];
        self.moved(c.node, c.x_ref, u)
    }

    /// The current position of local node `node` at reference position `x_ref` in the local
    /// state `u`.
    fn moved(&self, node: usize, x_ref: [f64; 3], u: &[f64]) -> [f64; 3] {
        let mut x = x_ref;
        for (k, &a) in self.axes().iter().enumerate() {
            x[a] += u[self.nc * node + k];
        }
        x
    }

    /// The Cartesian axis of each displacement component ((x, z) on the meridian).
    fn axes(&self) -> &'static [usize] {
        if self.nc == 2 {
            &[0, 2]
        } else {
            &[0, 1, 2]
        }
    }

    /// The nearest tool at x, the tools at `position`: (tool, φ, the normal ∇φ, ∇²φ, the closest
    /// point), in the node's components ((r, z) on the meridian).
    fn nearest_at(&self, x: [f64; 3], position: &[f64]) -> Option<(usize, Local)> {
        let mut best: Option<(usize, Local)> = None;
        for k in 0..self.tools.len() {
            let g = self.local_gap(k, x, position[k]);
            if best.as_ref().is_none_or(|(_, b)| g.phi < b.phi) {
                best = Some((k, g));
            }
        }
        best
    }

    /// Tool k's distance at x, the tool at `position`, in the node's components.
    fn local_gap(&self, k: usize, x: [f64; 3], position: f64) -> Local {
        let tool = &self.tools[k];
        if self.nc == 2 {
            let s = tool.meridian([x[0], x[2]], position);
            let [[a, b], [c, d]] = s.hess;
            Local {
                phi: s.phi,
                normal: [s.grad[0], s.grad[1], 0.0],
                hess: [[a, b, 0.0], [c, d, 0.0], [0.0; 3]],
                closest: [s.closest[0], s.closest[1], 0.0],
            }
        } else {
            let g = tool.gap(x, position);
            Local { phi: g.phi, normal: g.normal, hess: g.hess, closest: g.closest }
        }
    }

    /// The drainage's gap of local node `node` (reference position `x_ref`) in the local state
    /// `u`, the tools where the stage put them: the nearest sealing tool's φ and ∇φ in the node's
    /// components (None: no tool seals).
    pub(crate) fn seal_gap(&self, node: usize, x_ref: [f64; 3], u: &[f64]) -> Option<(f64, [f64; 3])> {
        let x = self.moved(node, x_ref, u);
        let position = self.positions.borrow();
        (0..self.tools.len())
            .filter(|&k| self.tools[k].seals)
            .map(|k| self.local_gap(k, x, position.d[k]))
            .min_by(|a, b| a.phi.total_cmp(&b.phi))
            .map(|g| (g.phi, g.normal))
    }

    /// The contact data of the local state `u` (owned + ghost, after the ghost exchange): the
    /// owned candidates' frames, computed here and shared with every rank (collective).
    pub(crate) fn update(&mut self, u: &[f64], dofs: &DofMap) {
        self.nodes.clear();
        let position = self.positions();
        // (first global u dof, n̂) of each owned framed node.
        let mut framed: Vec<f64> = Vec::new();
        for i in (0..self.candidates.len()).filter(|&i| self.candidates[i].node < self.n_owned_nodes) {
            let x = self.position_of(i, u);
            let Some((tool, mut g)) = self.nearest_at(x, &position).filter(|(_, g)| g.phi <= self.band) else {
                continue;
            };
            // A held component: the mirror-symmetric tool's normal and curvature have none there
            // (round-off taken out, so the frame keeps the component's axis bit for bit).
            // (On the meridian's axis n_r is 0 by construction and the frame ±I.)
            let held = self.candidates[i].held;
            if self.nc == 3 && held.iter().any(|&h| h) {
                for c in (0..3).filter(|&c| held[c]) {
                    g.normal[c] = 0.0;
                    for k in 0..3 {
                        (g.hess[c][k], g.hess[k][c]) = (0.0, 0.0);
                    }
                }
                let norm = g.normal.iter().map(|v| v * v).sum::<f64>().sqrt();
                g.normal = g.normal.map(|v| v / norm);
            }
            // σ = +1 with n̂ = ∇φ on the meridian; in space n̂ = ±∇φ with n̂_z ≥ 0 (the
            // rotation taking e_z to it is then well conditioned).
            let sigma = if self.nc == 2 || g.normal[2] >= 0.0 { 1.0 } else { -1.0 };
            let n = g.normal.map(|v| sigma * v);
            let node = self.candidates[i].node;
            let a = self.tools[tool].axis;
            let axis = if self.nc == 2 { [a[0], a[2], 0.0] } else { a };
            let frame = self.frame(n);
            self.nodes.push(NodeContact { node, frame, sigma, phi: g.phi, hess: g.hess, tool, axis });
            framed.extend([dofs.l2g[dofs.u_local(node, 0)] as f64, n[0], n[1], n[2]]);
        }
        self.frames.fill(None);
        for f in all_gather_vec(&self.world, &framed).chunks_exact(4) {
            if let Ok(k) = self.global_first.binary_search(&(f[0] as Int)) {
                self.frames[k] = Some(self.frame([f[1], f[2], f[3]]));
            }
        }
    }

    /// The frame of the normal n̂ (in the node's components): the same bits on every rank.
    fn frame(&self, n: [f64; 3]) -> Frame {
        if self.nc == 2 {
            Frame::meridian([n[0], n[1]])
        } else {
            Frame::spatial(n)
        }
    }

    /// The owned candidates in the local state `u`, the tools at `position`: (local node, current
    /// position, nearest tool).
    pub(crate) fn owned_gaps<'a>(
        &'a self,
        u: &'a [f64],
        position: &'a [f64],
    ) -> impl Iterator<Item = (usize, [f64; 3], Nearest)> + 'a {
        (0..self.candidates.len()).filter(|&i| self.candidates[i].node < self.n_owned_nodes).filter_map(move |i| {
            let x = self.position_of(i, u);
            let (tool, g) = self.nearest_at(x, position)?;
            Some((self.candidates[i].node, x, Nearest { tool, phi: g.phi }))
        })
    }
}

/// A tool's distance in a node's components.
struct Local {
    phi: f64,
    normal: [f64; 3],
    hess: [[f64; 3]; 3],
    closest: [f64; 3],
}

impl CurvedContact for ToolSet {
    fn components(&self) -> usize {
        self.nc
    }

    fn candidates(&self) -> &[Int] {
        &self.global_first
    }

    fn frames(&self) -> &[Option<Frame>] {
        &self.frames
    }

    fn nodes(&self) -> &[NodeContact] {
        &self.nodes
    }

    fn project(&self, x: &mut Vector) -> Result<f64> {
        let mut xv = x.write()?;
        let mut deepest = 0.0f64;
        let nc = self.nc;
        let position = self.positions();
        // The owned array starts with the owned nodes' u, as the local one does.
        for i in (0..self.candidates.len()).filter(|&i| self.candidates[i].node < self.n_owned_nodes) {
            let Some((k, g)) = self.nearest_at(self.position_of(i, &xv), &position) else { continue };
            if g.phi < 0.0 {
                deepest = deepest.max(-g.phi / (0.5 * self.tools[k].profile.thickness()));
                let c = &self.candidates[i];
                // The closest point, in the node's components ((r, z) on the meridian); a held
                // component stays (the closest point of a mirror-symmetric tool is in its plane).
                for (j, &a) in self.axes().iter().enumerate().filter(|&(j, _)| !c.held[j]) {
                    let target = if nc == 2 { g.closest[j] } else { g.closest[a] };
                    xv[nc * c.node + j] = target - c.x_ref[a];
                }
            }
        }
        Ok(deepest)
    }
}
