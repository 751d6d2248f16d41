//! Every fixture loads, and every mesh's half-edge structure is valid and of the expected kind.

use penumbra::geom::HalfEdgeMesh;

use crate::common::{fixture_names, load};

#[test]
fn every_fixture_loads_with_valid_half_edges() {
    for name in fixture_names() {
        let scene = load(&name);
        assert!(scene.triangle_count() > 0, "{name}");
        for m in scene.meshes.iter() {
            let h = HalfEdgeMesh::build(&m.mesh);
            h.validate()
                .unwrap_or_else(|e| panic!("{name}: {}: {e}", m.source.display()));
            assert!(
                !h.has_inconsistent_orientation(),
                "{name}: {}",
                m.source.display()
            );
            let file = m.source.file_name().unwrap().to_string_lossy();
            match &*file {
                "sphere.obj" => assert!(h.is_closed(), "{name}: sphere must be closed"),
                "quad.obj" => assert_eq!(h.edge_counts(), [4, 1, 0, 0]),
                "book.obj" => assert_eq!(h.edge_counts()[3], 1, "one edge with three faces"),
                // The real meshes copied from common-3d-test-models (fixtures/meshes), with the
                // triangle counts and topology its note gives them; edge_counts = [boundary,
                // manifold, inconsistent, non-manifold].
                "spot.obj" | "fandisk.obj" | "cheburashka.obj" => {
                    let triangles = match &*file {
                        "spot.obj" => 5856,
                        "fandisk.obj" => 12946,
                        _ => 13334,
                    };
                    assert_eq!(m.mesh.triangles.len(), triangles, "{name}: {file}");
                    assert!(h.is_closed(), "{name}: {file} must be closed");
                }
                "beetle.obj" => {
                    assert_eq!(m.mesh.triangles.len(), 2053, "{name}: beetle");
                    assert_eq!(
                        h.edge_counts(),
                        [296, 2861, 0, 47],
                        "{name}: beetle: 296 boundary edges, 47 in three faces"
                    );
                }
                "woody.obj" => {
                    assert_eq!(m.mesh.triangles.len(), 1267, "{name}: woody");
                    assert_eq!(h.edge_counts(), [119, 1841, 0, 0], "{name}: woody is open");
                    let p = &m.mesh.positions;
                    let [a, b, c] = m.mesh.triangles[0].map(|i| p[i as usize]);
                    let n = (b - a).cross(c - a).normalize();
                    assert!(
                        p.iter().all(|q| (*q - a).dot(n).abs() < 1e-9),
                        "{name}: woody must be planar"
                    );
                }
                other => panic!("unexpected fixture mesh {other}"),
            }
        }
    }
}

#[test]
fn sphere_has_760_triangles_and_spheres_9x9_has_81() {
    let s = load("spheres-9x9");
    let spheres: Vec<_> = s
        .meshes
        .iter()
        .filter(|m| m.source.ends_with("sphere.obj"))
        .collect();
    assert_eq!(spheres.len(), 81);
    assert!(spheres.iter().all(|m| m.mesh.triangles.len() == 760));
}

#[test]
fn geometry_counts_match_fixtures_expected() {
    use penumbra::volumes::GeometryCounts;
    for name in fixture_names() {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("fixtures/expected")
            .join(format!("{name}.json"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut want: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(
            want["how_checked"].is_string(),
            "{name}: say how the values were checked"
        );
        want.as_object_mut().unwrap().remove("how_checked");
        let scene = load(&name);
        let counts =
            |s: &penumbra::Scene| GeometryCounts::of(&penumbra::volumes::Volumes::build(&s.lit(0)));
        // A scene of several lights lists each light's counts, in order, under its name.
        if let Some(lights) = want.get("lights").and_then(|l| l.as_array()) {
            assert_eq!(
                scene.light_names(),
                lights
                    .iter()
                    .map(|l| l["name"].as_str().unwrap())
                    .collect::<Vec<_>>(),
                "{name}"
            );
            for (k, l) in lights.iter().enumerate() {
                let want: GeometryCounts = serde_json::from_value(l.clone()).unwrap();
                assert_eq!(counts(&scene.for_light(k)), want, "{name}: light {k}");
            }
            continue;
        }
        assert!(
            scene.single_channel(),
            "{name}: list each light's counts under \"lights\""
        );
        let want: GeometryCounts = serde_json::from_value(want).unwrap();
        assert_eq!(counts(&scene), want, "{name}");
    }
}
