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
    assert!(rows[0].starts_with("model") && rows[0].contains("accepted"));
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
        let share = m["accepted_share"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&share));
        assert!(m["sj_min"].as_f64().unwrap() <= m["sj_mean"].as_f64().unwrap());
    }
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
