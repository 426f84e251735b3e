//! Every [`Command`] applied: [`App::run_command`] matches the command and
//! forwards it to the handler of its area, each in a file of its own:
//! `step` (stepping, running, Cancel, finishing), `history` (undo, redo,
//! reset), `view` (the canvas view, file dialogs, quit), `file` (New,
//! Open, Save, Export), `train` (settings, corrections, refit, the
//! model), `samples` (the training set), `draw` (the boundary edited),
//! `regions` (a document of regions) and `compare` (the Compare panel).

mod compare;
mod draw;
mod file;
mod history;
mod regions;
mod samples;
mod step;
mod train;
mod view;

use super::{App, Command, EditorError};

impl App {
    /// Runs one command; its message for the status line.
    pub(super) fn run_command(&mut self, cmd: Command) -> Result<String, EditorError> {
        match cmd {
            Command::Step => self.step_once(),
            Command::StepN(n) => self.step_n(n),
            Command::RunToEnd => self.run_to_end(),
            Command::Animate(on) => self.set_animating(on),
            Command::Cancel => Ok(self.cancel()),
            Command::Finish => self.finish_again(),
            Command::Compare(names) => self.start_compare(&names),
            Command::StopCompare => self.stop_compare(),
            Command::Quit => self.quit(),
            Command::Undo => self.undo(),
            Command::Redo => self.redo(),
            Command::Reset => self.reset_mesh(),
            Command::FitView => self.fit_view(),
            Command::ZoomToStep => self.zoom_to_step(),
            Command::Dialog(d) => self.ask_file(d),
            Command::New => self.new_document(),
            Command::Open(path) => self.open_file(path),
            Command::OpenExample(name) => self.open_example(name),
            Command::Save => self.save_or_ask(),
            Command::SaveProject(path) => self.save(&path),
            Command::SaveBoundary(path) => self.save_boundary(path),
            Command::Export(path) => self.export(path),
            Command::SetSettings(s) => self.set_settings(s),
            Command::UseModel(path) => self.use_model(path),
            Command::AppendLast => self.append_last(),
            Command::CorrectLast {
                element_type,
                pn,
                snap_to,
            } => self.correct_last(element_type, pn, snap_to),
            Command::Refit { form, mesh_rest } => self.start_refit(form, mesh_rest),
            Command::SaveModel(path) => self.save_model(path),
            Command::ImportSamples(p) => self.import_samples(p),
            Command::ExportSamples(p) => self.export_samples(p),
            Command::DeleteSamples(idx) => self.delete_samples(idx),
            Command::CollectFromMesh => self.collect_from_mesh(),
            Command::CollectFromFile(p) => self.collect_from_file(p),
            Command::ToRegions => self.make_regions(),
            Command::SplitRegion { from, through, to } => self.split_region(from, through, to),
            Command::NameGroup {
                segments,
                name,
                tag,
            } => self.name_group(segments, name, tag),
            Command::NameRegion { at, name, tag } => self.name_region(at, name, tag),
            Command::SetSize(h) => self.set_size(h),
            Command::SetDraft { draft, what } => self.set_draft(draft, what),
        }
    }
}
