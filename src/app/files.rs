//! File dialogs (rfd, the desktop's own) and the recent-files list.

use super::command::{Command, Dialog};
use std::path::{Path, PathBuf};

/// Asks for a file with the desktop's dialog; `None` when the user
/// cancels (or the desktop has no dialog to offer).
pub fn pick(d: Dialog, dir: Option<&Path>, name: &str) -> Option<PathBuf> {
    let mut f = rfd::FileDialog::new();
    if let Some(dir) = dir {
        f = f.set_directory(dir);
    }
    match d {
        Dialog::Open => f
            .set_title("Open a boundary, project or quad mesh")
            .add_filter(
                "boundary, project or mesh",
                &["poly", "json", "msh", "msh22"],
            )
            .pick_file(),
        Dialog::SaveProjectAs => f
            .set_title("Save the project")
            .add_filter("quadex project", &["json"])
            .set_file_name(format!("{name}.quadex.json"))
            .save_file(),
        Dialog::ExportMesh => f
            .set_title("Export the mesh")
            .add_filter("Gmsh 4.1", &["msh"])
            .add_filter("Gmsh 2.2", &["msh22"])
            .add_filter("VTK", &["vtk"])
            .add_filter("VTU", &["vtu"])
            .add_filter("Abaqus", &["inp"])
            .add_filter("SVG", &["svg"])
            .set_file_name(format!("{name}.msh"))
            .save_file(),
        Dialog::ImportSamples => f
            .set_title("Import training samples")
            .add_filter("training set", &["csv", "json"])
            .pick_file(),
        Dialog::ExportSamples => f
            .set_title("Export training samples")
            .add_filter("CSV", &["csv"])
            .add_filter("JSON", &["json"])
            .set_file_name(format!("{name}_samples.csv"))
            .save_file(),
        Dialog::CollectFromFile => f
            .set_title("Collect samples from a quad mesh")
            .add_filter("Gmsh", &["msh"])
            .pick_file(),
        Dialog::ModelFile => f
            .set_title("Mesh with a fitted model")
            .add_filter("quadex model", &["json"])
            .pick_file(),
    }
}

/// The command a dialog's answer becomes.
pub fn command_for(d: Dialog, path: PathBuf) -> Command {
    match d {
        Dialog::Open => Command::Open(path),
        Dialog::SaveProjectAs => Command::SaveProject(path),
        Dialog::ExportMesh => Command::Export(path),
        Dialog::ImportSamples => Command::ImportSamples(path),
        Dialog::ExportSamples => Command::ExportSamples(path),
        Dialog::CollectFromFile => Command::CollectFromFile(path),
        Dialog::ModelFile => Command::UseModel(path),
    }
}

/// Files opened or saved lately, the newest first.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Recent(pub Vec<PathBuf>);

impl Recent {
    /// How many the list keeps.
    pub const LEN: usize = 10;

    pub fn push(&mut self, p: &Path) {
        self.0.retain(|q| q != p);
        self.0.insert(0, p.to_path_buf());
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
            r.push(Path::new(&format!("f{}", k % 12)));
        }
        r.push(Path::new("f5"));
        assert_eq!(r.0.len(), Recent::LEN);
        assert_eq!(r.0[0], Path::new("f5"));
        assert_eq!(r.0.iter().filter(|p| *p == Path::new("f5")).count(), 1);
    }
}
