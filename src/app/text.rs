//! Text the panels share: counts in words, ordinals, figures, and a table
//! that scrolls sideways.

/// A table wider than its panel: it scrolls sideways under a solid bar
/// that is always shown (a floating bar, shown on hover only, leaves the
/// clipped columns unannounced), and its rows are never wrapped.
pub fn sideways_table(ui: &mut egui::Ui, id: &str, table: impl FnOnce(&mut egui::Ui)) {
    ui.scope(|ui| {
        ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
        egui::ScrollArea::horizontal()
            .id_salt(id)
            .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
            .show(ui, |ui| {
                ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
                table(ui)
            });
    });
}

/// "1 quad", "2 quads".
pub fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The quads of `n` that miss a criterion `share` of them meet, as a
/// count ("3 of 198,007 outside"): a share rounded to 100.0 % would hide
/// them.
pub fn missing(share: f64, n: usize, word: &str) -> String {
    let met = (share * n as f64).round().clamp(0.0, n as f64) as usize;
    let miss = n - met;
    let grouped = crate::compare::grouped;
    if miss == 0 {
        format!("none of {} {word}", grouped(n))
    } else {
        format!("{} of {} {word}", grouped(miss), grouped(n))
    }
}

/// "1st", "2nd", "3rd", "4th", "11th", "22nd".
pub fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// A fit figure with `decimals`, or "n/a" when it is not finite.
pub fn figure(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "n/a".into()
    }
}

/// The stem of a document name: `plate.quadex.json` gives `plate`.
pub(super) fn stem(name: &str) -> String {
    let s = name.split('.').next().unwrap_or("");
    if s.is_empty() {
        "untitled".into()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_read_as_english() {
        assert_eq!(plural(1, "sample"), "1 sample");
        assert_eq!(plural(0, "sample"), "0 samples");
        assert_eq!(plural(3, "quad"), "3 quads");
        let o: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 23, 101, 111]
            .iter()
            .map(|&n| ordinal(n))
            .collect();
        assert_eq!(
            o,
            [
                "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "23rd",
                "101st", "111th"
            ]
        );
        assert_eq!(figure(f64::NEG_INFINITY, 4), "n/a");
        assert_eq!(figure(0.98765, 3), "0.988");
        assert_eq!(stem("plate.quadex.json"), "plate");
        assert_eq!(stem(""), "untitled");
        assert_eq!(
            missing(1.0 - 3.0 / 198_007.0, 198_007, "outside"),
            "3 of 198,007 outside"
        );
        assert_eq!(missing(1.0, 12, "outside"), "none of 12 outside");
    }
}
