//! Mesh files read in parallel. A `plymesh` or `objmesh` shape's file is not read where the
//! shape stands but when the parse ends, together with every other mesh file the scene names,
//! on all threads: real scenes name thousands of them, each small enough to decode on one
//! thread. What a reader sees is what reading each where it stands gives: the first file that
//! fails, in the scene's order, is the error (also when the parse stops later on an error of
//! its own), and each file's note sits among the warnings where the shape stands.

use std::path::PathBuf;
use std::sync::Arc;

use rayon::prelude::*;

use super::super::desc::ShapeGeometry;
use super::super::error::{Location, SceneError};
use super::super::shapes;
use super::Parser;

/// A mesh file to read, and where its mesh goes.
pub(super) struct PendingMesh {
    kind: &'static str,
    path: PathBuf,
    loc: Location,
    /// The shape's object (its index in `Parser::objects` once closed) and its index among the
    /// object's shapes, or among the world's.
    object: Option<usize>,
    shape: usize,
    /// Where the file's note goes in `Parser::warnings`.
    warning_at: usize,
}

impl Parser<'_> {
    /// The geometry of a `kind` ("plymesh" or "objmesh") shape reading `path`, about to be
    /// pushed at `loc`: empty until [`Self::read_mesh_files`] reads the file.
    pub(super) fn defer_mesh_file(&mut self, kind: &'static str, path: PathBuf, loc: &Location) -> ShapeGeometry {
        let (object, shape) = match &self.current_object {
            // Objects do not nest: the open one is the next to close.
            Some(o) => (Some(self.objects.len()), o.shapes.len()),
            None => (None, self.shapes.len()),
        };
        let warning_at = self.warnings.len();
        self.pending_meshes.push(PendingMesh { kind, path, loc: loc.clone(), object, shape, warning_at });
        ShapeGeometry::Mesh(Arc::default())
    }

    /// Reads every mesh file named so far, on all threads, into its shape (objects closed).
    pub(super) fn read_mesh_files(&mut self) -> Result<(), SceneError> {
        let pending = std::mem::take(&mut self.pending_meshes);
        let read: Vec<_> = pending.par_iter().map(|p| shapes::read_mesh_file(p.kind, &p.path, &p.loc)).collect();
        let mut notes = Vec::new();
        for (p, r) in pending.iter().zip(read) {
            let (mesh, note) = r?;
            let shape = match p.object {
                Some(o) => &mut self.objects[o].shapes[p.shape],
                None => &mut self.shapes[p.shape],
            };
            shape.geometry = ShapeGeometry::Mesh(Arc::new(mesh));
            notes.extend(note.map(|n| (p.warning_at, n)));
        }
        // Last first, so that the places of the earlier ones stay where they were.
        for (at, note) in notes.into_iter().rev() {
            self.warnings.insert(at, note);
        }
        Ok(())
    }

    /// After the parse stopped with `error`: the first mesh file named before it that cannot be
    /// read, which reading it where it stood would have stopped at, else `error`.
    pub(super) fn first_error(&self, error: SceneError) -> SceneError {
        let failed = self.pending_meshes.iter().find_map(|p| shapes::read_mesh_file(p.kind, &p.path, &p.loc).err());
        failed.unwrap_or(error)
    }
}
