//! The editor's mesher, run in the frame the command line meshes in.
//!
//! The command line meshes a boundary moved next to the origin
//! ([`Boundary::to_local`]: by its smallest coordinates where that move is
//! exact) and moves the finished mesh back. Steps are computed in floating
//! point, so a run in the file's own coordinates rounds differently and can
//! end in another mesh. [`Framed`] runs the editor's [`Mesher`] in the same
//! moved frame and speaks world coordinates to the rest of the editor: its
//! mesh, the Pn of its step reports and of the checked elements are moved
//! back, and the Pn of a user's correction is moved in. Recorded actions
//! ([`Mesher::actions`], saved in projects) stay in the mesher's frame, so
//! a replay takes them as they were taken.

use crate::extract::{
    Action, CheckedElement, Correction, MeshError, Mesher, RunProgress, StepOutcome, StepReport,
};
use crate::model::Model;
use crate::pipeline::{self, FinishParams};
use crate::{Boundary, MeshParams, Point, QuadMesh};
use std::ops::{ControlFlow, Deref};
use std::sync::{Arc, OnceLock};

/// A [`Mesher`] over a boundary moved by `-origin`, read in world
/// coordinates. Read-only calls go to the mesher itself (through `Deref`);
/// every call that changes it goes through here, so that the mesh in world
/// coordinates is made again when it is next read.
#[derive(Clone)]
pub struct Framed {
    inner: Mesher,
    origin: Point,
    /// The mesher's mesh moved back by `origin`, made when first read after
    /// a change (never at a zero origin, where the mesher's own mesh is the
    /// world's): a hundred steps in a row copy the mesh once, not a
    /// hundred times.
    world: OnceLock<Arc<QuadMesh>>,
}

impl Framed {
    /// A mesher over `boundary` in the frame the command line uses.
    pub fn new(boundary: Boundary, model: Arc<dyn Model>, params: MeshParams) -> Framed {
        let (local, origin) = boundary.to_local();
        Framed::at(local, origin, model, params)
    }

    /// A mesher over `boundary` in its own coordinates (projects saved
    /// before meshing moved the boundary recorded their actions so).
    pub fn unmoved(boundary: Boundary, model: Arc<dyn Model>, params: MeshParams) -> Framed {
        Framed::at(boundary, Point::ZERO, model, params)
    }

    fn at(local: Boundary, origin: Point, model: Arc<dyn Model>, params: MeshParams) -> Framed {
        Framed {
            inner: Mesher::new(local, model, params.moved(origin)),
            origin,
            world: OnceLock::new(),
        }
    }

    /// What the boundary was moved by (subtracted from its coordinates).
    pub fn origin(&self) -> Point {
        self.origin
    }

    /// The mesh as stepped, in world coordinates.
    pub fn mesh(&self) -> &QuadMesh {
        if self.origin == Point::ZERO {
            return self.inner.mesh();
        }
        self.world.get_or_init(|| {
            let mut m = self.inner.mesh().clone();
            pipeline::to_world(&mut m, self.origin);
            Arc::new(m)
        })
    }

    /// Drops the world mesh after a change (it is made again when read).
    fn refresh(&mut self) {
        self.world = OnceLock::new();
    }

    /// A report of the mesher's, in world coordinates.
    fn report(&self, r: StepReport) -> StepReport {
        moved_out(r, self.origin)
    }

    /// A correction given in world coordinates, in the mesher's frame.
    fn moved_in(&self, c: &Correction) -> Correction {
        Correction {
            pn: c.pn.map(|p| p - self.origin),
            ..c.clone()
        }
    }

    /// See [`Mesher::step`].
    pub fn step(&mut self) -> Result<StepOutcome, MeshError> {
        let out = self.inner.step();
        self.refresh();
        Ok(match out? {
            StepOutcome::Stepped(r) => StepOutcome::Stepped(Box::new(self.report(*r))),
            StepOutcome::Done => StepOutcome::Done,
        })
    }

    /// See [`Mesher::undo`].
    pub fn undo(&mut self) -> bool {
        let undone = self.inner.undo();
        self.refresh();
        undone
    }

    /// See [`Mesher::redo`].
    pub fn redo(&mut self) -> Result<Option<StepReport>, MeshError> {
        let out = self.inner.redo();
        self.refresh();
        Ok(out?.map(|r| self.report(r)))
    }

    /// Takes a recorded action ([`Mesher::take`]; its points are in the
    /// mesher's frame, as [`Mesher::actions`] keeps them).
    pub fn take(&mut self, a: &Action) -> Result<Option<StepReport>, MeshError> {
        let out = self.inner.take(a);
        self.refresh();
        Ok(out?.map(|r| self.report(r)))
    }

    /// See [`Mesher::correct`]; Pn in world coordinates.
    pub fn correct(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        let c = self.moved_in(c);
        let out = self.inner.correct(&c);
        self.refresh();
        Ok(self.report(out?))
    }

    /// See [`Mesher::check_correction`]; Pn and the element in world
    /// coordinates.
    pub fn check_correction(&mut self, c: &Correction) -> Result<CheckedElement, MeshError> {
        let c = self.moved_in(c);
        let mut e = self.inner.check_correction(&c)?;
        e.quad = e.quad.map(|p| p + self.origin);
        Ok(e)
    }

    /// See [`Mesher::set_model`].
    pub fn set_model(&mut self, model: Arc<dyn Model>) {
        self.inner.set_model(model);
        self.refresh();
    }

    /// See [`Mesher::run_with`]; `each` sees reports in world coordinates.
    pub fn run_with(
        &mut self,
        mut each: impl FnMut(&StepReport, RunProgress) -> ControlFlow<()>,
    ) -> Result<bool, MeshError> {
        let origin = self.origin;
        let out = self.inner.run_with(|r, at| {
            if origin == Point::ZERO {
                each(r, at)
            } else {
                each(&moved_out(r.clone(), origin), at)
            }
        });
        self.refresh();
        out
    }

    /// The finished mesh ([`pipeline::finish`]) in world coordinates,
    /// checked as the command line checks it.
    pub fn finish(&self, f: &FinishParams) -> Result<QuadMesh, MeshError> {
        pipeline::finish_moved(&self.inner, f, self.origin)
    }

    /// [`Framed::finish`], `phase` called as each part of it starts.
    pub fn finish_phased(
        &self,
        f: &FinishParams,
        phase: impl FnMut(pipeline::FinishPhase),
    ) -> Result<QuadMesh, MeshError> {
        pipeline::finish_phased(&self.inner, f, self.origin, phase)
    }
}

/// Step report `r` of a mesher run in a frame moved by `-origin`, moved
/// back (its only point is the model's Pn; the rest are node ids).
fn moved_out(mut r: StepReport, origin: Point) -> StepReport {
    r.predicted_pn = r.predicted_pn.map(|p| p + origin);
    r
}

impl Deref for Framed {
    type Target = Mesher;

    fn deref(&self) -> &Mesher {
        &self.inner
    }
}
