//! Undo and redo over every edit of the document. Steps are undone by the
//! mesher itself (it replays its actions, so a step costs nothing to keep);
//! every other edit (a correction, a training-set change, a refit, new
//! settings, a boundary edit, an opened file) keeps the document as it was
//! before, and undoing it swaps the two. Steps a refit's run takes belong
//! to the refit: one undo takes both back.

use super::document::{Document, Replayed};
use super::error::EditorError;
use std::path::PathBuf;

/// One undoable edit.
enum Entry {
    /// This many steps of the mesher, taken one after another.
    Steps(usize),
    /// The document before (on the undo stack) or after (on the redo stack)
    /// an edit, with the edit's name.
    State(Box<Document>, &'static str),
    /// An edit that replaced the whole document (New, Open): as `State`,
    /// with the project file that titles it and Save writes to, which
    /// the swap takes along.
    Replaced(Box<Document>, &'static str, Option<PathBuf>),
}

impl Entry {
    /// Puts a kept document (and a replaced one's project file) in place of
    /// the current ones; returns the entry that puts them back, and the
    /// edit's name. Steps are not kept documents: they come back as they
    /// are.
    fn swap(self, doc: &mut Document, project: &mut Option<PathBuf>) -> (Entry, &'static str) {
        match self {
            Entry::State(kept, name) => {
                let current = std::mem::replace(doc, *kept);
                (Entry::State(Box::new(current), name), name)
            }
            Entry::Replaced(kept, name, file) => {
                let current = std::mem::replace(doc, *kept);
                let current_file = std::mem::replace(project, file);
                (Entry::Replaced(Box::new(current), name, current_file), name)
            }
            steps @ Entry::Steps(_) => (steps, "step"),
        }
    }
}

/// The undo and redo stacks.
#[derive(Default)]
pub struct History {
    undo: Vec<Entry>,
    redo: Vec<Entry>,
}

/// Whole documents kept for undo, at most; older ones are dropped with
/// the steps below them.
pub const MAX_STATES: usize = 50;

/// What an undo or redo did to the document.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Undone {
    pub name: &'static str,
    /// A step, as opposed to a whole-document edit.
    pub step: bool,
}

impl History {
    /// Records `n` steps just taken.
    pub fn steps(&mut self, n: usize) {
        if n > 0 {
            push_steps(&mut self.undo, n);
            self.redo.clear();
        }
    }

    /// Records an edit: `before` is the document as it was.
    pub fn edit(&mut self, before: Document, name: &'static str) {
        self.undo.push(Entry::State(Box::new(before), name));
        self.redo.clear();
        let states = self
            .undo
            .iter()
            .filter(|e| !matches!(e, Entry::Steps(_)))
            .count();
        if states > MAX_STATES {
            if let Some(k) = self.undo.iter().position(|e| !matches!(e, Entry::Steps(_))) {
                self.undo.drain(..=k);
            }
        }
    }

    /// Marks the edit just recorded as one that replaced the whole
    /// document, which had the project file `project`.
    pub fn replaced(&mut self, project: Option<PathBuf>) {
        if let Some(Entry::State(before, name)) = self.undo.pop() {
            self.undo.push(Entry::Replaced(before, name, project));
        }
    }

    /// Records what opening a project replayed (after the "open" edit), so
    /// that its steps and refits undo one by one.
    pub fn replayed(&mut self, entries: Vec<Replayed>) {
        for e in entries {
            match e {
                Replayed::Steps(n) => push_steps(&mut self.undo, n),
                Replayed::Refit(before) => self.undo.push(Entry::State(before, "refit")),
            }
        }
        self.redo.clear();
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Undoes the last edit or step; returns what was undone. `project` is
    /// the document's project file, swapped back with a replaced document.
    pub fn undo(&mut self, doc: &mut Document, project: &mut Option<PathBuf>) -> Option<Undone> {
        match self.undo.pop()? {
            Entry::Steps(n) => {
                if n > 1 {
                    self.undo.push(Entry::Steps(n - 1));
                }
                if !doc.undo_step() {
                    // Steps the mesher no longer has are dropped, and undo
                    // goes on to the edit before them: a document of
                    // regions undoes steps within the face being meshed
                    // only, and a rewind or a run made again with balanced
                    // fans replaces steps with fewer.
                    if doc.regions.is_some() || doc.meshing.is_some() {
                        if n > 1 {
                            self.undo.pop();
                        }
                        return self.undo(doc, project);
                    }
                    return None;
                }
                push_steps(&mut self.redo, 1);
                Some(Undone {
                    name: "step",
                    step: true,
                })
            }
            kept => {
                let (back, name) = kept.swap(doc, project);
                self.redo.push(back);
                Some(Undone { name, step: false })
            }
        }
    }

    /// Redoes the last undone edit or step; returns what was redone (see
    /// [`History::undo`] for `project`).
    pub fn redo(
        &mut self,
        doc: &mut Document,
        project: &mut Option<PathBuf>,
    ) -> Result<Option<Undone>, EditorError> {
        let Some(e) = self.redo.pop() else {
            return Ok(None);
        };
        match e {
            Entry::Steps(n) => {
                if !doc.redo_step()? {
                    self.redo.clear();
                    return Ok(None);
                }
                if n > 1 {
                    self.redo.push(Entry::Steps(n - 1));
                }
                push_steps(&mut self.undo, 1);
                Ok(Some(Undone {
                    name: "step",
                    step: true,
                }))
            }
            kept => {
                let (back, name) = kept.swap(doc, project);
                self.undo.push(back);
                Ok(Some(Undone { name, step: false }))
            }
        }
    }

    /// What Undo would undo, for the menu.
    pub fn undo_name(&self) -> Option<&'static str> {
        name(self.undo.last())
    }

    /// What Redo would redo, for the menu.
    pub fn redo_name(&self) -> Option<&'static str> {
        name(self.redo.last())
    }
}

fn name(e: Option<&Entry>) -> Option<&'static str> {
    e.map(|e| match e {
        Entry::Steps(_) => "step",
        Entry::State(_, n) | Entry::Replaced(_, n, _) => n,
    })
}

/// Pushes `n` steps, merged with steps on top.
fn push_steps(stack: &mut Vec<Entry>, n: usize) {
    if let Some(Entry::Steps(m)) = stack.last_mut() {
        *m += n;
    } else {
        stack.push(Entry::Steps(n));
    }
}
