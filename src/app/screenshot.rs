//! The `--screenshot` option: a PNG of the window after the first frames.

use super::error::{EditorError, ScreenshotError};
use super::App;
use std::path::Path;

/// Frames drawn before a screenshot is taken (layout and view settle).
pub(super) const SCREENSHOT_FRAME: u64 = 3;

impl App {
    /// The `--screenshot` option: request a screenshot after the first
    /// frames, save it when it arrives, then close.
    pub(super) fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(path) = self.window.screenshot.clone() else {
            return;
        };
        if self.busy() || self.finishing() {
            ctx.request_repaint();
            return;
        }
        // The window at the size asked for first (eframe restores the
        // size of the last run before the first frame).
        let sized = self
            .window
            .size
            .is_none_or(|want| (ctx.content_rect().size() - want).length() < 1.0);
        if !self.window.screenshot_requested && self.window.frame >= SCREENSHOT_FRAME && sized {
            ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(Default::default()));
            self.window.screenshot_requested = true;
        }
        let shot = ctx.input(|i| {
            i.raw.events.iter().find_map(|e| match e {
                egui::Event::Screenshot { image, .. } => Some(image.clone()),
                _ => None,
            })
        });
        if let Some(img) = shot {
            match save_png(&img, &path) {
                Ok(()) => eprintln!("quadex: wrote {}", path.display()),
                Err(e) => eprintln!("quadex: {e}"),
            }
            self.window.screenshot = None;
            self.window.close_allowed = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else {
            ctx.request_repaint();
        }
    }
}

/// Saves a screenshot as PNG.
pub(super) fn save_png(img: &egui::ColorImage, path: &Path) -> Result<(), EditorError> {
    let [w, h] = img.size;
    let bytes: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_array()).collect();
    let err = |cause| EditorError::Screenshot {
        path: path.to_path_buf(),
        cause,
    };
    let len = bytes.len();
    let im = image::RgbaImage::from_raw(w as u32, h as u32, bytes).ok_or(err(
        ScreenshotError::Buffer {
            width: w,
            height: h,
            bytes: len,
        },
    ))?;
    im.save(path).map_err(|e| err(ScreenshotError::Png(e)))
}
