//! `quadex compare`: one boundary meshed by several models, a table and one
//! picture of the meshes side by side (thesis Figure 44).

mod common;

fn quadex(args: &[&std::ffi::OsStr]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn compare_meshes_a_boundary_with_each_model() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("cmp.svg");
    let report = dir.path().join("cmp.json");
    // A model file among the built-in ones.
    let file = dir.path().join("shipped.json");
    std::fs::write(&file, quadex::model::DEFAULT_MODEL_JSON).unwrap();
    let models = format!("default,rules,thesis,ann,{}", file.display());
    let annulus = common::bench().join("boundaries/annulus.poly");
    let o = quadex(&[
        "compare".as_ref(),
        annulus.as_os_str(),
        "--models".as_ref(),
        models.as_ref(),
        "-o".as_ref(),
        svg.as_os_str(),
        "--report".as_ref(),
        report.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(rows.len(), 6, "{table}");
    assert!(
        rows[0].starts_with("model")
            && rows[0].contains("accepted")
            && rows[0].contains("rescaled")
            && rows[0].contains("replaced"),
        "{table}"
    );
    for (row, name) in rows[1..]
        .iter()
        .zip(["default", "rules", "thesis", "ann", "shipped"])
    {
        assert!(row.starts_with(name), "{row}");
        assert!(row.contains("yes"), "{row}");
    }
    // The shipped model as a file meshes as `default` does.
    assert_eq!(rows[1]["default".len()..], rows[5]["shipped".len()..]);
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let ms = r["models"].as_array().unwrap();
    assert_eq!(ms.len(), 5);
    for m in ms {
        assert_eq!(m["finished"], true);
        assert!(m["quads"].as_u64().unwrap() > 200);
        // Every element step is accepted as predicted, rescaled or
        // replaced.
        let shares =
            ["accepted_share", "rescaled_share", "replaced_share"].map(|k| m[k].as_f64().unwrap());
        assert!(shares.iter().all(|s| (0.0..=1.0).contains(s)), "{m}");
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{m}");
        assert!(m["sj_min"].as_f64().unwrap() <= m["sj_mean"].as_f64().unwrap());
    }
    // The default model's rows are drawn towards the size field: those
    // steps are not counted as accepted as predicted.
    assert!(ms[0]["rescaled_share"].as_f64().unwrap() > 0.0, "{}", ms[0]);
    let pic = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(pic.matches("<svg ").count(), 6);
    for name in ["default", "rules", "thesis", "ann", "shipped"] {
        assert!(pic.contains(&format!(">{name}</text>")), "{name}");
    }

    // Bad input: exit 2, one line, nothing written.
    let out = dir.path().join("none.svg");
    let o = quadex(&[
        "compare".as_ref(),
        annulus.as_os_str(),
        "--models".as_ref(),
        "default,nosuch.json".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1);
    assert!(err.contains("nosuch.json"), "{err}");
    assert!(!out.exists());
}

#[test]
fn steps_whose_pn_was_rescaled_are_not_counted_as_accepted() {
    use quadex::extract::{Remedy, StepKind, RESCALED_BEYOND};
    use quadex::{ElementType, MeshParams, Mesher, StepOutcome};
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/plate_hole.poly")).unwrap();
    let model: std::sync::Arc<dyn quadex::Model> =
        std::sync::Arc::from(quadex::model::builtin("default").unwrap());
    let mut m = Mesher::new(b.clone(), model.clone(), MeshParams::DEFAULT);
    let (mut accepted, mut rescaled) = (0, 0);
    while let StepOutcome::Stepped(r) = m.step().unwrap() {
        if r.kind != StepKind::Element || r.element_type != Some(ElementType::New) {
            continue;
        }
        // How far the element's new node lies from the model's Pn, in the
        // normalised frame (units of |P_r1 − P0|).
        let nodes = &m.mesh().nodes;
        let mid = r.leading.len() / 2;
        let d = nodes[r.leading[mid] as usize].distance(nodes[r.leading[mid + 1] as usize]);
        let at = nodes[r.pn_node().unwrap() as usize];
        let moved = at.distance(r.predicted_pn.unwrap()) / d;
        match r.remedy {
            Remedy::None => {
                assert!(moved <= RESCALED_BEYOND + 1e-9, "step {}: {moved}", r.index);
                accepted += 1;
            }
            Remedy::Rescaled => {
                assert!(moved > RESCALED_BEYOND, "step {}: {moved}", r.index);
                rescaled += 1;
            }
            _ => {}
        }
    }
    assert!(accepted > 0 && rescaled > 0, "{accepted} {rescaled}");
    assert_eq!(m.stats().remedies(Remedy::Rescaled), rescaled);
    // The comparison's shares count them apart and add up.
    let o = quadex::compare::mesh_with("default", &b, model, &quadex::Params::DEFAULT);
    let elements = m.stats().count(StepKind::Element) as f64;
    assert!((o.rescaled_share - rescaled as f64 / elements).abs() < 1e-12);
    assert!((o.accepted_share + o.rescaled_share + o.replaced_share - 1.0).abs() < 1e-12);
}
