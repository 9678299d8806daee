use super::*;
use crate::fmu::inspect::{inspect, read_entry};
use std::io::Read;

/// Schilder et al.'s 2-DOF network (the shipped example file).
const SEED: &str = include_str!("../../../examples/networks/seed_2dof.xml");

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hydrofmu-archive-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn hull() -> Body {
    Body {
        name: "Test hull".into(),
        dofs: vec![
            DofUnit::builtin("sway").unwrap(),
            DofUnit::builtin("roll").unwrap(),
        ],
        xml: Some(
            Hull::semicircle(1.0)
                .unwrap()
                .select_dofs(&["sway", "roll"])
                .unwrap()
                .to_xml_string(),
        ),
        extent: Extent::PerUnitLength,
        hydrostatics_csv: None,
        excitation_csv: None,
        drift_csv: None,
        viscous: None,
        crossflow_csv: None,
        report: None,
    }
}

fn net(text: &str) -> PackedNetwork {
    PackedNetwork::from_text(text.to_string(), "test network").unwrap()
}

/// An FMI 2.0 archive of `network` for `body` with a stand-in binary.
fn archive(body: Body, network: &str, id: &str) -> Archive {
    Archive::new(body, net(network), id, b"\x7fELF fake".to_vec())
}

#[test]
fn the_archive_has_the_fmi_layout_and_matching_guid() {
    let dir = temp_dir("layout");
    let out = dir.join("Seed-1.fmu");
    let id = identifier_from_path(&out);
    assert_eq!(id, "Seed_1");
    let packed = archive(hull(), SEED, &id).build().unwrap();
    assert_eq!(packed.dofs, vec!["sway".to_string()]);
    assert_eq!(packed.states, 4);
    let beside = packed.write(&out).unwrap().unwrap();
    let found = inspect(&out).unwrap();
    assert_eq!(found.guid, packed.guid);
    assert_eq!(found.resources_guid, packed.guid);
    assert_eq!(found.model_identifier, "Seed_1");
    assert_eq!(found.dofs, vec![("sway".to_string(), "m/s".to_string())]);
    let osp_name = format!("{}_OspModelDescription.xml", found.model_name);
    // The members in the archive's documented order.
    assert_eq!(
        found.entries,
        vec![
            "modelDescription.xml".to_string(),
            "binaries/linux64/Seed_1.so".into(),
            "resources/network.xml".into(),
            "resources/options.xml".into(),
            "resources/hull.xml".into(),
            "documentation/index.html".into(),
            format!("extra/com.open-simulation-platform/{osp_name}"),
        ]
    );
    // The OSP model description beside the archive is the one inside it.
    assert_eq!(beside, dir.join(&osp_name));
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&out).unwrap()).unwrap();
    let inside = read_entry(
        &mut zip,
        &format!("extra/com.open-simulation-platform/{osp_name}"),
    )
    .unwrap();
    assert_eq!(inside, Some(std::fs::read_to_string(&beside).unwrap()));
    for i in 0..zip.len() {
        let f = zip.by_index(i).unwrap();
        assert_eq!(f.compression(), zip::CompressionMethod::Deflated);
        assert_eq!(f.unix_mode(), Some(0o100644));
        assert!(!f.name().contains('\\'));
        assert!(!f.is_symlink());
    }
    // The binary is a byte copy.
    let mut so = Vec::new();
    zip.by_name("binaries/linux64/Seed_1.so")
        .unwrap()
        .read_to_end(&mut so)
        .unwrap();
    assert_eq!(so, b"\x7fELF fake");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_same_inputs_give_the_same_bytes() {
    let first = archive(hull(), SEED, "M").build().unwrap();
    let second = archive(hull(), SEED, "M").build().unwrap();
    assert_eq!(first.bytes, second.bytes);
    let other = archive(hull(), SEED, "N").build().unwrap();
    assert_ne!(first.bytes, other.bytes);
}

#[test]
fn an_fmi3_archive_has_the_fmi3_layout_and_the_same_guid() {
    let dir = temp_dir("fmi3");
    let (two, three) = (dir.join("Two.fmu"), dir.join("Three.fmu"));
    let s2 = archive(hull(), SEED, "M").build().unwrap();
    s2.write(&two).unwrap();
    let mut fmi3 = archive(hull(), SEED, "M");
    fmi3.fmi = FmiVersion::V3;
    let s3 = fmi3.build().unwrap();
    s3.write(&three).unwrap();
    assert_eq!(s3.guid, s2.guid);
    let found = inspect(&three).unwrap();
    assert_eq!(found.fmi_version, "3.0");
    assert_eq!(inspect(&two).unwrap().fmi_version, "2.0");
    assert_eq!(found.guid, s3.guid);
    assert_eq!(found.dofs, vec![("sway".to_string(), "m/s".to_string())]);
    assert!(found
        .entries
        .contains(&"binaries/x86_64-linux/M.so".to_string()));
    assert!(!found.entries.iter().any(|e| e.contains("linux64")));
    // time, 10 fixed parameters, velocity, force, power, energy, 3 arrays, the waves'
    // force_radiation, force_excitation and wave.elevation.
    assert_eq!(found.variables, 1 + 10 + 4 + 3 + 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn guids_differ_between_networks_hulls_and_flags() {
    let guid = |network: &str, body: Body, keep: bool| {
        let mut a = archive(body, network, "M");
        a.keep_inf_mass = keep;
        a.build().unwrap().guid
    };
    let other_net = SEED.replace("0.1153", "0.1154");
    let mut other_hull = hull();
    other_hull.xml = Some(
        Hull::semicircle(2.0)
            .unwrap()
            .select_dofs(&["sway", "roll"])
            .unwrap()
            .to_xml_string(),
    );
    let a = guid(SEED, hull(), false);
    assert_eq!(a, guid(SEED, hull(), false));
    assert_ne!(a, guid(&other_net, hull(), false));
    assert_ne!(a, guid(SEED, other_hull, false));
    assert_ne!(a, guid(SEED, hull(), true));
}

#[test]
fn scene_documentation_and_reports_are_packed() {
    let mut with_scene = archive(hull(), SEED, "M");
    with_scene.scene = Some(SceneDocumentation {
        scene: "DOFs modelled      sway".into(),
        fit: "network: coupled".into(),
        plots: vec![("fit-sway-sway.svg".into(), "<svg/>".into())],
    });
    let packed = with_scene.build().unwrap();
    assert_eq!(packed.scene.as_deref(), Some("DOFs modelled      sway"));
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(packed.bytes)).unwrap();
    let names: Vec<String> = zip.file_names().map(str::to_string).collect();
    let at = |n: &str| names.iter().position(|e| e == n).unwrap();
    assert!(at("documentation/index.html") < at("documentation/plots/fit-sway-sway.svg"));
    assert!(at("documentation/plots/fit-sway-sway.svg") < at(SCENE_FILE));
    let scene = read_entry(&mut zip, SCENE_FILE).unwrap().unwrap();
    assert_eq!(scene, "DOFs modelled      sway\n");
    let html = read_entry(&mut zip, "documentation/index.html")
        .unwrap()
        .unwrap();
    assert!(
        html.contains("<img src=\"plots/fit-sway-sway.svg\""),
        "{html}"
    );
    assert!(html.ends_with("</body></html>\n"));

    let mut whole = hull();
    whole.report = Some("ship a & b".into());
    let packed = archive(whole, SEED, "M").build().unwrap();
    assert_eq!(packed.scene.as_deref(), Some("ship a & b"));
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(packed.bytes)).unwrap();
    let html = read_entry(&mut zip, "documentation/index.html")
        .unwrap()
        .unwrap();
    assert!(
        html.contains("<h2>Fit report</h2>\n<pre>ship a &amp; b</pre>"),
        "{html}"
    );
}

#[test]
fn mistakes_are_reported_clearly() {
    let dir = temp_dir("errors");
    let mut h = hull();
    h.dofs.remove(0);
    let e = archive(h, SEED, "X").build().unwrap_err();
    assert!(e.0.contains("'sway' is not a DOF"), "{e}");
    let e = PackedNetwork::from_text("<nonsense".into(), "network.xml").unwrap_err();
    assert!(e.0.contains("network"), "{e}");
    let e = read_binary(&dir.join("missing.so")).unwrap_err();
    assert!(e.0.contains("cannot read the binary"), "{e}");
    let not_zip = dir.join("lib.so");
    std::fs::write(&not_zip, b"x").unwrap();
    assert!(inspect(&not_zip).is_err());
    let e = archive(hull(), SEED, "X")
        .build()
        .unwrap()
        .write(&dir.join("missing/X.fmu"))
        .unwrap_err();
    assert!(e.0.contains("cannot write"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
