//! `traxer inspect`: on meshes built here with known geometry, the counts, the
//! bounding box and the area are exact, the topology faults are found where they
//! were put, the units hint names the unit, and broken files give exit code 2 with
//! the tracer's own message.

use crate::common::{broken_mesh_files, gltf_with_nodes, write};
use serde_json::Value;
use std::path::Path;

/// Runs `traxer inspect --json` and returns (exit code, JSON, stderr).
fn inspect(files: &[&Path], extra: &[&str]) -> (i32, Value, String) {
    let out = crate::common::traxer()
        .arg("inspect")
        .arg("--json")
        .args(files)
        .args(extra)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!err.contains("panicked"), "panic: {err}");
    let json = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
    (out.status.code().unwrap_or(-1), json, err)
}

/// The report of one file that must import.
fn inspect_ok(file: &Path, extra: &[&str]) -> Value {
    let (code, json, err) = inspect(&[file], extra);
    assert_eq!(code, 0, "{}: {err}", file.display());
    assert_eq!(json["traxer_inspect"], 1);
    let f = json["files"][0].clone();
    assert_eq!(f["imported"], true);
    f
}

fn count(v: &Value, key: &str) -> u64 {
    v[key]
        .as_u64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

fn bounds(v: &Value) -> [[f64; 3]; 2] {
    let b = |k: &str| -> [f64; 3] {
        let a = v["bounds"][k].as_array().expect("bounds");
        [0, 1, 2].map(|i| a[i].as_f64().unwrap())
    };
    [b("min"), b("max")]
}

fn assert_bounds(v: &Value, min: [f64; 3], max: [f64; 3], tol: f64) {
    let [lo, hi] = bounds(v);
    for i in 0..3 {
        assert!(
            (lo[i] - min[i]).abs() <= tol && (hi[i] - max[i]).abs() <= tol,
            "bounds {lo:?}..{hi:?}, expected {min:?}..{max:?}"
        );
    }
}

/// Topology counts in one go: (degenerate, boundary, non-manifold, inconsistent
/// winding, components).
fn topology(v: &Value) -> [u64; 5] {
    [
        "degenerate_triangles",
        "boundary_edges",
        "non_manifold_edges",
        "inconsistent_winding_edges",
        "components",
    ]
    .map(|k| count(v, k))
}

/// The unit cube [0,1]³ as OBJ: 8 shared vertices, 6 outward-wound quads (the
/// importer triangulates them). `faces` may reverse or drop some.
const CUBE_VERTICES: &str =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
const CUBE_FACES: [&str; 6] = [
    "f 1 4 3 2", // z = 0, facing −z
    "f 5 6 7 8", // z = 1, +z
    "f 1 2 6 5", // y = 0, −y
    "f 3 4 8 7", // y = 1, +y
    "f 1 5 8 4", // x = 0, −x
    "f 2 3 7 6", // x = 1, +x
];

fn cube_obj(faces: &[String]) -> String {
    format!("o cube\n{CUBE_VERTICES}{}\n", faces.join("\n"))
}

fn reversed(face: &str) -> String {
    let mut idx: Vec<&str> = face.split_whitespace().skip(1).collect();
    idx.reverse();
    format!("f {}", idx.join(" "))
}

#[test]
fn unit_cube_counts_bounds_area_and_orientation_are_exact() {
    let dir = tempfile::tempdir().unwrap();
    let faces: Vec<String> = CUBE_FACES.iter().map(|f| f.to_string()).collect();
    let f = inspect_ok(&write(dir.path(), "cube.obj", &cube_obj(&faces)), &[]);
    let t = &f["total"];
    assert_eq!(count(t, "parts"), 1);
    assert_eq!(count(t, "triangles"), 12);
    assert_eq!(count(t, "vertices"), 8);
    assert_eq!(count(t, "distinct_positions"), 8);
    assert_bounds(t, [0.0; 3], [1.0; 3], 0.0);
    assert_eq!(num(t, "area"), 6.0);
    assert_eq!(topology(t), [0, 0, 0, 0, 1]);
    assert_eq!(t["closed"], true);
    assert!((num(t, "enclosed_volume") - 1.0).abs() < 1e-12, "{t}");
    assert_eq!(t["normals"], "computed");
    assert!(t["normals_against_winding"].is_null());
    // 12 cube edges at 90°; the quads' diagonals are flat.
    assert_eq!(count(t, "creases"), 12);
    assert_eq!(num(t, "facet_step_deg"), 0.0);
    assert_eq!(f["parts"][0]["name"], "cube");
    assert_eq!(f["parts"][0]["primitives"][0]["label"], "object 'cube'");

    // Inside out: every face reversed → still closed, negative volume.
    let inside_out: Vec<String> = CUBE_FACES.iter().map(|f| reversed(f)).collect();
    let t = inspect_ok(&write(dir.path(), "inv.obj", &cube_obj(&inside_out)), &[])["total"].clone();
    assert_eq!(topology(&t), [0, 0, 0, 0, 1]);
    assert!((num(&t, "enclosed_volume") + 1.0).abs() < 1e-12, "{t}");

    // One face reversed: its 4 rim edges join neighbours wound the other way.
    let mut one = faces.clone();
    one[3] = reversed(CUBE_FACES[3]);
    let t = inspect_ok(&write(dir.path(), "one.obj", &cube_obj(&one)), &[])["total"].clone();
    assert_eq!(topology(&t), [0, 0, 0, 4, 1]);
    assert_eq!(t["closed"], true);
    assert!(t["enclosed_volume"].is_null());
}

#[test]
fn split_vertices_are_welded_and_file_normals_are_checked_against_winding() {
    // The cube as CAD exports it: 4 vertices and one normal per face (24 in all).
    let corners: Vec<[f64; 3]> = CUBE_VERTICES
        .lines()
        .map(|l| {
            let v: Vec<f64> = l[2..].split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let normals = ["0 0 -1", "0 0 1", "0 -1 0", "0 1 0", "-1 0 0", "1 0 0"];
    let build = |flip_face: Option<usize>| {
        let mut text = String::from("o split\n");
        for (k, face) in CUBE_FACES.iter().enumerate() {
            for i in face.split_whitespace().skip(1) {
                let c = corners[i.parse::<usize>().unwrap() - 1];
                text += &format!("v {} {} {}\n", c[0], c[1], c[2]);
            }
            let n = if flip_face == Some(k) {
                normals[k]
                    .split(' ')
                    .map(|x| format!("{}", -x.parse::<f64>().unwrap()))
                    .collect::<Vec<_>>()
                    .join(" ")
            } else {
                normals[k].to_string()
            };
            text += &format!("vn {n}\n");
            let b = 4 * k;
            text += &format!(
                "f {}//{k1} {}//{k1} {}//{k1} {}//{k1}\n",
                b + 1,
                b + 2,
                b + 3,
                b + 4,
                k1 = k + 1
            );
        }
        text
    };
    let dir = tempfile::tempdir().unwrap();
    let t = inspect_ok(&write(dir.path(), "split.obj", &build(None)), &[])["total"].clone();
    assert_eq!(count(&t, "vertices"), 24);
    assert_eq!(count(&t, "distinct_positions"), 8);
    assert_eq!(
        topology(&t),
        [0, 0, 0, 0, 1],
        "welded: no holes at the creases"
    );
    assert!((num(&t, "enclosed_volume") - 1.0).abs() < 1e-12);
    assert_eq!(t["normals"], "file");
    assert_eq!(count(&t, "normals_against_winding"), 0);
    // One face's normals flipped: its two triangles contradict their winding.
    let t = inspect_ok(&write(dir.path(), "flip.obj", &build(Some(2))), &[])["total"].clone();
    assert_eq!(count(&t, "normals_against_winding"), 2);
}

#[test]
fn holes_fins_and_degenerate_triangles_are_counted() {
    let dir = tempfile::tempdir().unwrap();
    // The cube without its top: 10 triangles, area 5, a 4-edge rim.
    let open: Vec<String> = CUBE_FACES
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != 1)
        .map(|(_, f)| f.to_string())
        .collect();
    let t = inspect_ok(&write(dir.path(), "open.obj", &cube_obj(&open)), &[])["total"].clone();
    assert_eq!(count(&t, "triangles"), 10);
    assert_eq!(num(&t, "area"), 5.0);
    assert_eq!(topology(&t), [0, 4, 0, 0, 1]);
    assert_eq!(t["closed"], false);
    assert!(t["enclosed_volume"].is_null());

    // A 3 × 3 grid of unit quads in z = 0 with the centre quad missing: 8 quads,
    // outer rim 12 edges, hole 4 edges.
    let mut text = String::from("o frame\n");
    for j in 0..4 {
        for i in 0..4 {
            text += &format!("v {i} {j} 0\n");
        }
    }
    for j in 0..3 {
        for i in 0..3 {
            if (i, j) != (1, 1) {
                let v = |i: usize, j: usize| 4 * j + i + 1;
                text += &format!(
                    "f {} {} {} {}\n",
                    v(i, j),
                    v(i + 1, j),
                    v(i + 1, j + 1),
                    v(i, j + 1)
                );
            }
        }
    }
    let t = inspect_ok(&write(dir.path(), "frame.obj", &text), &[])["total"].clone();
    assert_eq!(count(&t, "triangles"), 16);
    assert_eq!(num(&t, "area"), 8.0);
    assert_eq!(topology(&t), [0, 16, 0, 0, 1]);
    assert_bounds(&t, [0.0; 3], [3.0, 3.0, 0.0], 0.0);

    // Two triangles of a unit square whose shared corner (1,0,0) is written twice,
    // the second copy moved by δ: welded below 1e-6 of the diagonal (√2), a crack
    // above it.
    for (delta, boundary, distinct) in [(1e-7, 4, 4), (1e-5, 6, 5)] {
        let text = format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv {} 0 0\nv 1 1 0\nf 1 2 3\nf 4 5 3\n",
            1.0 + delta
        );
        let t = inspect_ok(&write(dir.path(), "crack.obj", &text), &[])["total"].clone();
        assert_eq!(count(&t, "boundary_edges"), boundary, "δ = {delta}");
        assert_eq!(count(&t, "distinct_positions"), distinct, "δ = {delta}");
    }

    // Zero area to f32 precision (height 5e-10 of the longest side) is degenerate;
    // a thin but real triangle (height 1e-5 of it) is not.
    let text = "v 0 0 0\nv 1 0 0\nv 2 1e-9 0\nv 0 1e-5 0\nf 1 2 3\nf 1 2 4\n";
    let t = inspect_ok(&write(dir.path(), "thin.obj", text), &[])["total"].clone();
    assert_eq!(count(&t, "degenerate_triangles"), 1);

    // A fin: three triangles on the edge (0,0,0)–(1,0,0); a collinear sliver and
    // a triangle with a repeated corner (both degenerate); a separate triangle.
    let text = "o fin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 2 0 0\n\
                v 5 5 5\nv 6 5 5\nv 5 6 5\n\
                f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 6\nf 3 3 5\nf 7 8 9\n";
    let t = inspect_ok(&write(dir.path(), "fin.obj", text), &[])["total"].clone();
    assert_eq!(count(&t, "triangles"), 6);
    // Edge 1–2 has three proper triangles and the sliver (1,2,6) on it.
    assert_eq!(count(&t, "non_manifold_edges"), 1);
    assert_eq!(count(&t, "degenerate_triangles"), 2);
    // Rims: 2 per fin triangle, 2 for the sliver, 3 for the lone triangle.
    assert_eq!(count(&t, "boundary_edges"), 3 * 2 + 2 + 3);
    assert_eq!(
        count(&t, "components"),
        2,
        "the fin (with both degenerate ones) and the lone triangle"
    );
    assert!(
        (num(&t, "area") - 2.0).abs() < 1e-15,
        "3 × 0.5 + 0.5 (lone)"
    );
}

#[test]
fn tessellated_cone_section_matches_its_closed_form() {
    // A Wolter-I-like cone segment: radius 63.2384 → 60.9121 over z 229 → 4, 30°.
    let (r1, z1, r2, z2) = (63.2384_f64, 229.0_f64, 60.9121_f64, 4.0_f64);
    let (segments, rings) = (40usize, 5usize);
    let dir = tempfile::tempdir().unwrap();
    let tess = |azimuth: &str, file: &str| {
        let out = dir.path().join(file);
        let st = crate::common::traxer()
            .args(["tessellate", "--shape"])
            .arg(format!(
                "type=\"cone\", radius_start={r1}, z_start={z1}, radius_end={r2}, z_end={z2}{azimuth}"
            ))
            .args(["--segments", &segments.to_string(), "--rings", &rings.to_string(), "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
        out
    };
    // Each facet between two rings and two azimuths is a planar isosceles
    // trapezoid: parallel chords 2 r sin(Δφ/2), height √(Δz² + (Δr cos(Δφ/2))²).
    let facet_area = |dphi: f64| -> f64 {
        (0..rings)
            .map(|j| {
                let (ra, rb) = (
                    r1 + (r2 - r1) * j as f64 / rings as f64,
                    r1 + (r2 - r1) * (j + 1) as f64 / rings as f64,
                );
                let dz = (z2 - z1) / rings as f64;
                let half = dphi / 2.0;
                (ra + rb) * half.sin() * (dz * dz + ((rb - ra) * half.cos()).powi(2)).sqrt()
            })
            .sum::<f64>()
            * segments as f64
    };
    // glTF stores f32: positions are good to ~1e-7 relative.
    let rel = 1e-6;

    let f = inspect_ok(&tess(", azimuth=[-15, 15]", "segment.gltf"), &[]);
    let t = &f["total"];
    assert_eq!(count(t, "triangles"), (2 * segments * rings) as u64);
    assert_eq!(count(t, "vertices"), ((segments + 1) * (rings + 1)) as u64);
    assert_eq!(topology(t), [0, 2 * (segments + rings) as u64, 0, 0, 1]);
    let area = facet_area(30f64.to_radians() / segments as f64);
    assert!(
        (num(t, "area") / area - 1.0).abs() < rel,
        "{} vs {area}",
        num(t, "area")
    );
    let s15 = 15f64.to_radians().sin();
    assert_bounds(
        t,
        [r2 * 15f64.to_radians().cos(), -r1 * s15, z2],
        [r1, r1 * s15, z1],
        1e-4,
    );
    assert_eq!(t["normals"], "file");
    assert_eq!(count(t, "normals_against_winding"), 0);
    // Neighbouring facets turn by Δφ about the axis; their normals, inclined by
    // the cone's half-angle a to the radial direction, bend by
    // acos(cos²a cos Δφ + sin²a). No creases.
    let a = ((r1 - r2) / (z1 - z2)).atan();
    let dphi = (30.0 / segments as f64).to_radians();
    let step = (a.cos().powi(2) * dphi.cos() + a.sin().powi(2))
        .acos()
        .to_degrees();
    assert!(
        (num(t, "facet_step_deg") - step).abs() < 1e-3,
        "{} vs {step}",
        num(t, "facet_step_deg")
    );
    assert_eq!(count(t, "creases"), 0);
    assert_eq!(f["units"]["suspected_unit"], "mm");
    assert!(f["units"]["scale"].is_null());

    // The full circle: the seam is shared, so only the two rims are open.
    let t = inspect_ok(&tess("", "full.gltf"), &[])["total"].clone();
    assert_eq!(count(&t, "vertices"), (segments * (rings + 1)) as u64);
    assert_eq!(topology(&t), [0, 2 * segments as u64, 0, 0, 1]);
    let area = facet_area(std::f64::consts::TAU / segments as f64);
    assert!((num(&t, "area") / area - 1.0).abs() < rel);
    assert_bounds(&t, [-r1, -r1, z2], [r1, r1, z1], 1e-4);
}

#[test]
fn gltf_hierarchy_is_placed_as_the_tracer_places_it() {
    // Node 0 "assembly": translate (100, 0, 0), scale 2, children 1 and 2 (both
    // instance mesh 0, the triangle (0,0,0), (1,0,0), (0,1,0)): node 1 "a" moves
    // it by (0, 0, 10), node 2 "b" turns it 90° about z. Node 3 lies in the second
    // scene only, which is not the default one, and must not appear. Mesh 0 also
    // has a LINES primitive, which is skipped.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let nodes = format!(
        r#"[{{"name":"assembly","translation":[100,0,0],"scale":[2,2,2],"children":[1,2]}},
           {{"name":"a","translation":[0,0,10],"mesh":0}},
           {{"name":"b","rotation":[0,0,{s},{s}],"mesh":0}},
           {{"name":"elsewhere","translation":[0,0,-1000],"mesh":0}}]"#
    );
    let dir = tempfile::tempdir().unwrap();
    let text = gltf_with_nodes(
        &nodes,
        &["[0]", "[3]"],
        r#",{"attributes":{"POSITION":0},"mode":1}"#,
    );
    let f = inspect_ok(&write(dir.path(), "h.gltf", &text), &[]);
    let parts = f["parts"].as_array().unwrap();
    let names: Vec<&str> = parts.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["a", "b"]);
    assert!(parts[0]["aliases"]
        .as_array()
        .unwrap()
        .contains(&Value::from("assembly")));
    // a: 100 + 2·(v + (0,0,10)) → x 100..102, y 0..2, z 20; area 0.5·2².
    assert_bounds(&parts[0], [100.0, 0.0, 20.0], [102.0, 2.0, 20.0], 1e-6);
    // b: 100 + 2·Rz(90°)·v → (100,0,0), (100,2,0), (98,0,0).
    assert_bounds(&parts[1], [98.0, 0.0, 0.0], [100.0, 2.0, 0.0], 1e-6);
    for p in parts {
        assert!((num(p, "area") - 2.0).abs() < 1e-6);
        assert_eq!(count(p, "triangles"), 1);
        assert_eq!(p["primitives"].as_array().unwrap().len(), 1);
        assert_eq!(p["normals"], "computed");
    }
    let t = &f["total"];
    assert_eq!(count(t, "parts"), 2);
    assert_bounds(t, [98.0, 0.0, 0.0], [102.0, 2.0, 20.0], 1e-6);
    assert!((num(t, "area") - 4.0).abs() < 1e-6);
    assert_eq!(count(t, "components"), 2);
    assert_eq!(
        f["notes"][0],
        "the file has 2 scenes: only scene 0 (the default) is read"
    );
    // One skipped entry per placement of the mesh's LINES primitive.
    let skipped = f["skipped"].as_array().unwrap();
    assert_eq!(skipped.len(), 2, "{skipped:?}");
    assert_eq!(skipped[0]["what"], "primitive 1 of mesh #0");
    assert!(skipped[0]["reason"].as_str().unwrap().contains("Lines"));
}

#[test]
fn units_hint_names_metres_and_inches_and_the_scale() {
    let dir = tempfile::tempdir().unwrap();
    // A 0.45 × 0.2 × 0.2 box: a telescope exported in metres.
    let obj = "v 0 0 0\nv 0.2 0 0\nv 0.2 0.2 0\nv 0 0.2 0.45\nf 1 2 3\nf 1 3 4\n";
    let p = write(dir.path(), "metres.obj", obj);
    let u = inspect_ok(&p, &[])["units"].clone();
    assert_eq!(u["suspected_unit"], "m");
    assert_eq!(num(&u, "scale"), 1000.0);
    assert!((num(&u, "largest_extent") - 0.45).abs() < 1e-12);
    assert!(
        u["message"]
            .as_str()
            .unwrap()
            .contains("{ scale = 1000.0 }"),
        "{u}"
    );
    // The user says it should be 11.4 mm: inches.
    let u = inspect_ok(&p, &["--expect-size", "11.4"])["units"].clone();
    assert_eq!(u["suspected_unit"], "in");
    assert_eq!(num(&u, "scale"), 25.4);
    // Expected 450 mm: metres again; expected 0.45 mm: it is millimetres.
    let u = inspect_ok(&p, &["--expect-size", "450"])["units"].clone();
    assert_eq!(u["suspected_unit"], "m");
    let u = inspect_ok(&p, &["--expect-size", "0.45"])["units"].clone();
    assert_eq!(u["suspected_unit"], "mm");
    assert!(u["scale"].is_null());
    // A factor of 3.16 is no unit (1 and 10 are both more than 1.5 times off).
    let u = inspect_ok(&p, &["--expect-size", "1.42"])["units"].clone();
    assert!(u["suspected_unit"].is_null() && u["scale"].is_null(), "{u}");
    // Following the advice: the scene's `{ scale = 1000.0 }` makes it 450 mm long.
    let scene = write(
        dir.path(),
        "s.toml",
        "[[objects]]\nname = \"t\"\nmaterial = \"absorber\"\n\
         shape = { type = \"mesh\", file = \"metres.obj\" }\ntransform = [{ scale = 1000.0 }]\n",
    );
    let loaded = traxer::scene::Scene::load(&crate::common::device(), &scene, &[]).unwrap();
    let traxer::scene::ObjectGeometry::Mesh(m) = &loaded.objects[0].geometry else {
        panic!("a mesh object")
    };
    let z_max = m.positions.iter().map(|p| p.z).fold(0.0, f64::max);
    assert!((z_max - 450.0).abs() < 1e-9, "{z_max}");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // Without the scale the tracer itself warns.
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("transform = [{ scale = 1000.0 }]\n", "");
    let unscaled = write(dir.path(), "s.toml", &text);
    let loaded = traxer::scene::Scene::load(&crate::common::device(), &unscaled, &[]).unwrap();
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("only 0.4500 mm across") && w.contains("{ scale = 1000.0 }")),
        "{:?}",
        loaded.warnings
    );
}

#[test]
fn broken_files_exit_2_with_the_tracers_message() {
    let dir = tempfile::tempdir().unwrap();
    for (file, content, needles) in broken_mesh_files() {
        let p = dir.path().join(file);
        std::fs::write(&p, &content).unwrap();
        let (code, json, err) = inspect(&[&p], &[]);
        assert_eq!(code, 2, "{file}: {err}");
        let f = &json["files"][0];
        assert_eq!(f["imported"], false, "{file}");
        let message = f["error"]
            .as_str()
            .unwrap_or_else(|| panic!("{file}: {json}"));
        assert!(message.contains(file), "{message}");
        for n in &needles {
            assert!(message.contains(n), "{file}: {message} lacks {n}");
        }
        assert!(err.contains(&format!("error: {message}")), "{err}");
        // The tracer, given the same file in a scene, says the same.
        let scene = write(
            dir.path(),
            "s.toml",
            &format!("[[objects]]\nname = \"x\"\nmaterial = \"absorber\"\nshape = {{ type = \"mesh\", file = \"{file}\" }}\n"),
        );
        let trace = crate::common::traxer()
            .arg("trace")
            .arg(&scene)
            .output()
            .unwrap();
        let trace_err = String::from_utf8_lossy(&trace.stderr);
        assert_eq!(trace.status.code(), Some(2));
        assert!(
            trace_err.contains(message),
            "{file}:\ntrace: {trace_err}\ninspect: {message}"
        );
    }
    // The lines-only file still lists what was skipped.
    let (_, json, _) = inspect(&[&dir.path().join("lines.gltf")], &[]);
    assert_eq!(
        json["files"][0]["skipped"][0]["what"],
        "primitive 0 of mesh #0"
    );

    // Several files: every one is reported, the good one imports, exit code 2.
    let good = write(
        dir.path(),
        "good.obj",
        &cube_obj(&CUBE_FACES.map(String::from)),
    );
    let (code, json, err) = inspect(
        &[
            &good,
            &dir.path().join("nan.obj"),
            &dir.path().join("nope.glb"),
        ],
        &[],
    );
    assert_eq!(code, 2, "{err}");
    let imported: Vec<bool> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["imported"].as_bool().unwrap())
        .collect();
    assert_eq!(imported, [true, false, false]);
    assert!(err.contains("2 of 3 files cannot be imported"), "{err}");

    // Not a mesh format; a nonsense expected size.
    let (code, json, _) = inspect(&[&write(dir.path(), "part.step", "ISO-10303-21;\n")], &[]);
    assert_eq!(code, 2);
    assert!(json["files"][0]["error"]
        .as_str()
        .unwrap()
        .contains("unsupported file type"));
    let out = crate::common::traxer()
        .args(["inspect", "--expect-size=-3"])
        .arg(&good)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--expect-size"));
}

#[test]
fn required_compression_names_the_primitives_that_use_it() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],
"extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"name":"shell","primitives":[{"attributes":{},"extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0}}}}]}],
"buffers":[{"byteLength":4}],"bufferViews":[{"buffer":0,"byteLength":4}]}"#;
    let p = write(dir.path(), "draco.gltf", text);
    let (code, json, _) = inspect(&[&p], &[]);
    assert_eq!(code, 2);
    let message = json["files"][0]["error"].as_str().unwrap();
    assert!(
        message.contains("KHR_draco_mesh_compression (used by primitive 0 of mesh 'shell')"),
        "{message}"
    );
}

#[test]
fn text_report_shows_the_same_facts() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "cube.obj",
        &cube_obj(&CUBE_FACES.map(String::from)),
    );
    let out = crate::common::traxer()
        .arg("inspect")
        .arg(&p)
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "1 part, 12 triangles, 8 vertices",
        "x [0, 1]  y [0, 1]  z [0, 1]",
        "area 6 mm^2",
        "0 boundary edges",
        "Closed: encloses 1 mm^3",
        // 1 unit is too small for millimetres: the metre hint.
        "add `{ scale = 1000.0 }` as the first step",
    ] {
        assert!(text.contains(needle), "lacks {needle:?}:\n{text}");
    }
}
