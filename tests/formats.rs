//! Export round trips: every writer produces a parseable file; MSH 4.1 and
//! 2.2 read back to the same mesh; writes are atomic.

mod common;

use quadex::io::{msh, write_mesh, MeshFormat};
use quadex::model::RulesModel;
use std::sync::Arc;

fn mesh(name: &str) -> quadex::QuadMesh {
    let b = quadex::io::read_boundary(&common::bench().join(format!("boundaries/{name}.poly")))
        .unwrap();
    quadex::mesh_boundary(
        &b,
        Arc::new(RulesModel::DEFAULT),
        &quadex::Params::DEFAULT,
        |_| {},
    )
    .unwrap()
    .0
}

#[test]
fn msh_round_trips() {
    let m = mesh("annulus");
    for fmt in [MeshFormat::Msh41, MeshFormat::Msh22] {
        let back = msh::read_msh(&fmt.render(&m)).unwrap();
        assert_eq!(back.quads.len(), m.quads.len());
        assert_eq!(back.nodes.len(), m.nodes.len());
        assert_eq!(back.loops.len(), 2);
        assert_eq!(back.n_boundary(), m.n_boundary());
        back.check_finished().unwrap();
        let q0 = quadex::MeshQuality::of(&m);
        let q1 = quadex::MeshQuality::of(&back);
        assert!((q0.sj_mean - q1.sj_mean).abs() < 1e-12);
    }
}

#[test]
fn every_format_writes_atomically() {
    let m = mesh("square");
    let dir = tempfile::tempdir().unwrap();
    for fmt in MeshFormat::ALL {
        let path = dir.path().join(format!("m.{}", fmt.extension()));
        write_mesh(&m, &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, fmt.render(&m));
        assert!(!text.is_empty());
    }
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    // A failed write leaves nothing behind.
    assert!(write_mesh(&m, &dir.path().join("missing/dir/m.msh")).is_err());
    assert!(write_mesh(&m, &dir.path().join("m.xyz")).is_err());
}

#[test]
fn vtk_carries_quad_cells_and_fields() {
    let m = mesh("square");
    let t = MeshFormat::Vtk.render(&m);
    assert!(t.contains(&format!("CELL_TYPES {}", m.quads.len())));
    assert!(t.contains("SCALARS scaled_jacobian double 1"));
    let inp = MeshFormat::Abaqus.render(&m);
    assert!(inp.contains("*ELEMENT, TYPE=CPS4, ELSET=DOMAIN"));
    assert!(inp.contains("*SURFACE, TYPE=ELEMENT, NAME=OUTER"));
    let msh = MeshFormat::Msh41.render(&m);
    assert!(msh.contains("$Entities") && msh.contains("\"domain\"") && msh.contains("\"outer\""));
}
