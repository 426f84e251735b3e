//! Asking for files: the desktop's own dialogs (rfd: the XDG portal, or
//! zenity) where the desktop has one, else (and always from "Type a
//! path…") a prompt in the window with the path prefilled; and the
//! recent-files list.

use super::command::{Command, Dialog};
use std::path::{Path, PathBuf};

impl Dialog {
    /// The title of the dialog.
    pub fn title(self) -> &'static str {
        match self {
            Dialog::Open => "Open a boundary, project or quad mesh",
            Dialog::SaveProjectAs => "Save the project as",
            Dialog::SaveBoundaryAs => "Save the boundary as (.poly or .json)",
            Dialog::ExportMesh => "Export the mesh (.msh .msh22 .vtk .vtu .inp .svg)",
            Dialog::ImportSamples => "Import training samples (.csv or .json)",
            Dialog::ExportSamples => "Export training samples (.csv or .json)",
            Dialog::CollectFromFile => "Collect samples from a quad mesh (.msh)",
            Dialog::ModelFile => "Mesh with a fitted model file (.json)",
            Dialog::SaveModel => "Save the refitted model as (.json)",
        }
    }

    /// True when the dialog names a file to write.
    pub fn saves(self) -> bool {
        matches!(
            self,
            Dialog::SaveProjectAs
                | Dialog::SaveBoundaryAs
                | Dialog::ExportMesh
                | Dialog::ExportSamples
                | Dialog::SaveModel
        )
    }

    /// The file name offered for a document named `stem`.
    pub fn file_name(self, stem: &str) -> String {
        match self {
            Dialog::SaveProjectAs => format!("{stem}.quadex.json"),
            Dialog::SaveBoundaryAs => format!("{stem}.poly"),
            Dialog::ExportMesh => format!("{stem}.msh"),
            Dialog::ExportSamples => format!("{stem}_samples.csv"),
            Dialog::SaveModel => format!("{stem}_model.json"),
            _ => String::new(),
        }
    }
}

/// True when the desktop offers file dialogs: a session bus (for the XDG
/// portal) or zenity on the path. `QUADEX_DIALOGS=builtin` forces the
/// prompt in the window.
pub fn native_dialogs() -> bool {
    if std::env::var("QUADEX_DIALOGS").is_ok_and(|v| v == "builtin") {
        return false;
    }
    if cfg!(any(target_os = "windows", target_os = "macos")) {
        return true;
    }
    let on_path = |exe: &str| {
        std::env::var_os("PATH")
            .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(exe).is_file()))
    };
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some() || on_path("zenity")
}

/// Asks for a file with the desktop's dialog, starting in `dir` with
/// `name` offered; `None` when the user cancels.
pub fn pick(d: Dialog, dir: Option<&Path>, name: &str) -> Option<PathBuf> {
    let mut f = rfd::FileDialog::new().set_title(d.title());
    if let Some(dir) = dir {
        f = f.set_directory(dir);
    }
    if !name.is_empty() {
        f = f.set_file_name(name);
    }
    match d {
        Dialog::Open => f
            .add_filter(
                "boundary, drawing, project or mesh",
                &["poly", "json", "dxf", "msh", "msh22"],
            )
            .pick_file(),
        Dialog::SaveProjectAs => f.add_filter("quadex project", &["json"]).save_file(),
        Dialog::SaveBoundaryAs => f
            .add_filter("Triangle .poly", &["poly"])
            .add_filter("JSON", &["json"])
            .save_file(),
        Dialog::ExportMesh => f
            .add_filter("Gmsh 4.1", &["msh"])
            .add_filter("Gmsh 2.2", &["msh22"])
            .add_filter("VTK", &["vtk"])
            .add_filter("VTU", &["vtu"])
            .add_filter("Abaqus", &["inp"])
            .add_filter("SVG", &["svg"])
            .save_file(),
        Dialog::ImportSamples => f.add_filter("training set", &["csv", "json"]).pick_file(),
        Dialog::ExportSamples => f
            .add_filter("CSV", &["csv"])
            .add_filter("JSON", &["json"])
            .save_file(),
        Dialog::CollectFromFile => f.add_filter("Gmsh", &["msh", "msh22"]).pick_file(),
        Dialog::ModelFile => f.add_filter("quadex model", &["json"]).pick_file(),
        Dialog::SaveModel => f.add_filter("quadex model", &["json"]).save_file(),
    }
}

/// The command a dialog's answer becomes.
pub fn command_for(d: Dialog, path: PathBuf) -> Command {
    match d {
        Dialog::Open => Command::Open(path),
        Dialog::SaveProjectAs => Command::SaveProject(path),
        Dialog::SaveBoundaryAs => Command::SaveBoundary(path),
        Dialog::ExportMesh => Command::Export(path),
        Dialog::ImportSamples => Command::ImportSamples(path),
        Dialog::ExportSamples => Command::ExportSamples(path),
        Dialog::CollectFromFile => Command::CollectFromFile(path),
        Dialog::ModelFile => Command::UseModel(path),
        Dialog::SaveModel => Command::SaveModel(path),
    }
}

/// The prompt for a path in the window (when the desktop has no dialog).
#[derive(Clone, Debug, PartialEq)]
pub struct Prompt {
    pub dialog: Dialog,
    pub path: String,
    /// Focus the path field on the first frame.
    focus: bool,
}

impl Prompt {
    pub fn new(dialog: Dialog, dir: &Path, name: &str) -> Prompt {
        let path = if name.is_empty() {
            format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR)
        } else {
            dir.join(name).display().to_string()
        };
        Prompt {
            dialog,
            path,
            focus: true,
        }
    }

    /// Draws the prompt; returns the command to run when the user answers
    /// (`Some(None)`: cancelled).
    pub fn ui(&mut self, ctx: &egui::Context, recent: &Recent) -> Option<Option<Command>> {
        let mut answer = None;
        let modal = egui::Modal::new(egui::Id::new("file_prompt")).show(ctx, |ui| {
            ui.set_width(520.0);
            ui.heading(self.dialog.title());
            let edit = ui.add(
                egui::TextEdit::singleline(&mut self.path)
                    .desired_width(f32::INFINITY)
                    .hint_text("a path"),
            );
            if std::mem::take(&mut self.focus) {
                edit.request_focus();
            }
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if self.dialog == Dialog::Open && !recent.0.is_empty() {
                ui.label("Recent:");
                for p in recent.0.iter().take(5) {
                    if ui.link(p.display().to_string()).clicked() {
                        self.path = p.display().to_string();
                    }
                }
            }
            ui.horizontal(|ui| {
                let ok = if self.dialog.saves() { "Save" } else { "Open" };
                let path = PathBuf::from(self.path.trim());
                let ready = !self.path.trim().is_empty() && !path.is_dir();
                if ui.add_enabled(ready, egui::Button::new(ok)).clicked() || (enter && ready) {
                    answer = Some(Some(command_for(self.dialog, path)));
                }
                if ui.button("Cancel").clicked() {
                    answer = Some(None);
                }
            });
        });
        if modal.should_close() && answer.is_none() {
            answer = Some(None);
        }
        answer
    }
}

/// Files opened or saved lately that Open reads ([`super::document::opens`]),
/// the newest first.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Recent(pub Vec<PathBuf>);

impl Recent {
    /// How many the list keeps.
    pub const LEN: usize = 10;

    /// Puts `p` first, unless Open cannot read it (a mesh exported to
    /// `.vtk`, say): the list is for opening again.
    pub fn push(&mut self, p: &Path) {
        if !super::document::opens(p) {
            return;
        }
        let p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        self.0.retain(|q| *q != p);
        self.0.insert(0, p);
        self.0.truncate(Self::LEN);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recent_files_are_unique_newest_first_and_bounded() {
        let mut r = Recent::default();
        for k in 0..15 {
            r.push(Path::new(&format!("/d/f{}.poly", k % 12)));
        }
        r.push(Path::new("/d/f5.poly"));
        assert_eq!(r.0.len(), Recent::LEN);
        assert_eq!(r.0[0], Path::new("/d/f5.poly"));
        assert_eq!(
            r.0.iter().filter(|p| *p == Path::new("/d/f5.poly")).count(),
            1
        );
    }

    #[test]
    fn recent_files_are_files_open_reads() {
        let mut r = Recent::default();
        for f in [
            "a.poly", "b.msh", "c.vtk", "d.vtu", "e.inp", "f.svg", "g.json", "h.MSH22",
        ] {
            r.push(Path::new("/d").join(f).as_path());
        }
        let names: Vec<_> = r.0.iter().filter_map(|p| p.file_name()?.to_str()).collect();
        assert_eq!(names, ["h.MSH22", "g.json", "b.msh", "a.poly"]);
    }
}
