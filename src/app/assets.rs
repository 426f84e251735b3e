//! The example boundaries the editor offers, built into the binary so that
//! an installed `quadex` opens them from any directory.

/// `(file name, text)` of every shipped example, sorted by name: `.poly`
/// boundaries, a regions document (`.json`) of several materials with
/// named boundary groups, and a drawing (`.dxf`: lines, arcs and circles
/// on named layers).
pub const EXAMPLES: [(&str, &str); 9] = [
    (
        "annulus.poly",
        include_str!("../../assets/examples/annulus.poly"),
    ),
    (
        "freemesh_boundary6.poly",
        include_str!("../../assets/examples/freemesh_boundary6.poly"),
    ),
    (
        "lshape.poly",
        include_str!("../../assets/examples/lshape.poly"),
    ),
    (
        "machine.json",
        include_str!("../../assets/examples/machine.json"),
    ),
    (
        "naca0012.poly",
        include_str!("../../assets/examples/naca0012.poly"),
    ),
    ("part.dxf", include_str!("../../assets/examples/part.dxf")),
    (
        "plate_hole.poly",
        include_str!("../../assets/examples/plate_hole.poly"),
    ),
    (
        "square.poly",
        include_str!("../../assets/examples/square.poly"),
    ),
    (
        "star8.poly",
        include_str!("../../assets/examples/star8.poly"),
    ),
];

/// The example the editor opens when no file is given.
pub const DEFAULT_EXAMPLE: &str = "annulus.poly";

/// The text of the example named `name`.
pub fn example(name: &str) -> Option<&'static str> {
    EXAMPLES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_example_is_built_in_and_valid() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".poly") || n.ends_with(".json") || n.ends_with(".dxf"))
            .collect();
        on_disk.sort();
        let built_in: Vec<&str> = EXAMPLES.iter().map(|(n, _)| *n).collect();
        assert_eq!(on_disk, built_in);
        for (name, text) in EXAMPLES {
            if name.ends_with(".json") {
                let g =
                    crate::io::regions_json::parse(text).unwrap_or_else(|e| panic!("{name}: {e}"));
                assert!(g.faces().unwrap().len() > 1, "{name}");
            } else if name.ends_with(".dxf") {
                let g = crate::cad::parse_dxf(text).unwrap_or_else(|e| panic!("{name}: {e}"));
                assert!(!g.curves.is_empty(), "{name}");
            } else {
                crate::io::poly::parse_poly(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            }
        }
        assert!(example(DEFAULT_EXAMPLE).is_some());
    }
}
