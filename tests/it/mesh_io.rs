//! glTF and OBJ import: hierarchy transforms, buffer layouts, primitive modes,
//! normals, and export round trips.

use crate::common::gltf_with_nodes;
use glam::DVec3;
use traxer::geometry::{AzimuthRange, Resolution, RevolutionQuadric, Shape, Surface};
use traxer::mesh::{load, write_mesh};

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

#[test]
fn gltf_node_hierarchy_transforms_are_applied() {
    // root: translate (10, 0, 0), rotate 90° about z, scale 2; child: matrix that
    // translates by (0, 0, 5). Expected world = T(10,0,0)·Rz(90)·S(2)·T(0,0,5)·v.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let nodes = format!(
        r#"[{{"translation":[10,0,0],"rotation":[0,0,{s},{s}],"scale":[2,2,2],"children":[1]}},
           {{"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1],"mesh":0}}]"#
    );
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("h.gltf");
    std::fs::write(&p, gltf_with_nodes(&nodes, &["[0]"], "")).unwrap();
    let (m, report) = load(&p).unwrap();
    assert!(!report.normals_from_file, "the file has no normals");
    let expect = |v: DVec3| {
        let v = v + DVec3::new(0., 0., 5.);
        let v = v * 2.0;
        let v = DVec3::new(-v.y, v.x, v.z);
        v + DVec3::new(10., 0., 0.)
    };
    assert_eq!(m.triangles.len(), 1);
    for (got, local) in m.positions.iter().zip([DVec3::ZERO, DVec3::X, DVec3::Y]) {
        assert!(
            close(*got, expect(local), 1e-6),
            "{got} vs {}",
            expect(local)
        );
    }
    // Computed normal: the triangle's plane, CCW → +z.
    assert!(close(m.normals.as_ref().unwrap()[0], DVec3::Z, 1e-9));
}

#[test]
fn gltf_mirroring_node_reverses_winding_and_other_modes_are_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.gltf");
    // scale z by −1 flips handedness; a LINES primitive (mode 1) is skipped.
    std::fs::write(
        &p,
        gltf_with_nodes(
            r#"[{"scale":[1,1,-1],"mesh":0}]"#,
            &["[0]"],
            r#",{"attributes":{"POSITION":0},"mode":1}"#,
        ),
    )
    .unwrap();
    let (m, report) = load(&p).unwrap();
    assert_eq!(m.triangles.len(), 1);
    assert_eq!(report.skipped.len(), 1, "{:?}", report.skipped);
    assert!(
        report.skipped[0].what == "primitive 1 of mesh #0"
            && report.skipped[0].reason.contains("Lines"),
        "{:?}",
        report.skipped
    );
    // The mirrored triangle (0,0,0),(1,0,0),(0,1,0) keeps its place, and its
    // winding is reversed so that the front stays where glTF says it is.
    assert!(m.face_normal(0).z < 0.0);
}

#[test]
fn gltf_triangle_strips_fans_and_external_buffers() {
    let dir = tempfile::tempdir().unwrap();
    // A unit quad as a strip (zig-zag order) and as a fan (around the rim).
    let strip = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]];
    let fan = [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    for (mode, n, verts) in [(5, 2, strip), (6, 2, fan)] {
        let mut bin = Vec::new();
        for v in verts {
            for c in v {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        std::fs::write(dir.path().join(format!("quad{mode}.bin")), &bin).unwrap();
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":{mode}}}]}}],
"buffers":[{{"byteLength":48,"uri":"quad{mode}.bin"}}],"bufferViews":[{{"buffer":0,"byteLength":48}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
        );
        let p = dir.path().join(format!("m{mode}.gltf"));
        std::fs::write(&p, text).unwrap();
        let (m, _) = load(&p).unwrap();
        assert_eq!(m.triangles.len(), n, "mode {mode}");
        // Both decompositions of the unit quad cover area 1 with one orientation.
        assert!(
            (m.area() - 1.0).abs() < 1e-6,
            "mode {mode}: area {}",
            m.area()
        );
        assert!(
            m.face_normal(0).z > 0.0 && m.face_normal(1).z > 0.0,
            "mode {mode}: winding"
        );
    }
}

#[test]
fn export_and_import_round_trip_in_every_format() {
    let shape = Shape::Revolution(RevolutionQuadric::cone(
        63.2384,
        229.0,
        60.9121,
        4.0,
        AzimuthRange::new(-15.0, 30.0),
    ));
    let m = shape.tessellate(Resolution {
        segments: 50,
        rings: 5,
    });
    let dir = tempfile::tempdir().unwrap();
    for name in ["c.gltf", "c.glb", "c.obj"] {
        let p = dir.path().join(name);
        write_mesh(&p, &m, "cone").unwrap();
        let (back, report) = load(&p).unwrap();
        assert!(
            report.normals_from_file && report.warnings().is_empty(),
            "{name}"
        );
        // OBJ readers may renumber vertices: compare triangle by triangle.
        assert_eq!(back.triangles.len(), m.triangles.len(), "{name}");
        // glTF stores f32; OBJ keeps f64 text.
        let tol = if name.ends_with("obj") { 1e-12 } else { 1e-5 };
        let (bn, mn) = (back.normals.as_ref().unwrap(), m.normals.as_ref().unwrap());
        for (tb, tm) in back.triangles.iter().zip(&m.triangles) {
            for (&kb, &km) in tb.iter().zip(tm) {
                let (a, b) = (back.positions[kb as usize], m.positions[km as usize]);
                assert!(close(a, b, tol), "{name}: {a} vs {b}");
                assert!(
                    close(bn[kb as usize], mn[km as usize], 1e-6),
                    "{name}: normals differ"
                );
            }
        }
    }
}

#[test]
fn obj_polygons_are_triangulated_and_normals_kept_or_computed() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("q.obj");
    std::fs::write(&p, "v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nf 1 2 3 4\n").unwrap();
    let (m, r) = load(&p).unwrap();
    assert_eq!(m.triangles.len(), 2);
    assert!((m.area() - 6.0).abs() < 1e-12);
    assert!(!r.normals_from_file);
    assert!(m
        .normals
        .unwrap()
        .iter()
        .all(|n| close(*n, DVec3::Z, 1e-12)));
    std::fs::write(
        &p,
        "v 0 0 0\nv 2 0 0\nv 2 3 0\nvn 0 0.6 0.8\nf 1//1 2//1 3//1\n",
    )
    .unwrap();
    let (m, r) = load(&p).unwrap();
    assert!(r.normals_from_file);
    assert!(m
        .normals
        .unwrap()
        .iter()
        .all(|n| close(*n, DVec3::new(0.0, 0.6, 0.8), 1e-6)));
}

#[test]
fn several_named_parts_in_one_file_round_trip_and_are_selected_by_name() {
    use traxer::mesh::{load_parts, select_parts, write_mesh_parts};
    let cone = |r: f64| {
        Shape::Revolution(RevolutionQuadric::cone(
            r,
            0.0,
            r - 2.0,
            100.0,
            AzimuthRange::FULL,
        ))
        .tessellate(Resolution {
            segments: 12,
            rings: 2,
        })
    };
    let (a, b) = (cone(50.0), cone(60.0));
    let dir = tempfile::tempdir().unwrap();
    for name in ["p.gltf", "p.glb", "p.obj"] {
        let p = dir.path().join(name);
        write_mesh_parts(&p, &[("inner", &a), ("outer", &b)]).unwrap();
        let (parts, _) = load_parts(&p).unwrap();
        let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["inner", "outer"], "{name}");
        let outer = select_parts(&p, &parts, Some("outer")).unwrap();
        assert_eq!(outer.triangles.len(), b.triangles.len(), "{name}");
        // Every vertex of the selected part lies on the outer cone (r = 60 − z/50).
        for q in &outer.positions {
            assert!(
                (q.truncate().length() - (60.0 - q.z / 50.0)).abs() < 1e-4,
                "{name}"
            );
        }
        let all = select_parts(&p, &parts, None).unwrap();
        assert_eq!(all.triangles.len(), a.triangles.len() + b.triangles.len());
        let e = select_parts(&p, &parts, Some("middle"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no part named `middle`") && e.contains("inner, outer"),
            "{e}"
        );
    }
}

#[test]
fn gltf_parts_can_be_picked_by_an_ancestor_node_name() {
    use traxer::mesh::{load_parts, select_parts};
    // "assembly" → "part_a" (mesh) and "part_b" (mesh): a CAD sub-assembly.
    let nodes = r#"[{"name":"assembly","children":[1,2]},
                    {"name":"part_a","mesh":0},
                    {"name":"part_b","mesh":0,"translation":[0,0,3]}]"#;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.gltf");
    std::fs::write(&p, gltf_with_nodes(nodes, &["[0]"], "")).unwrap();
    let (parts, _) = load_parts(&p).unwrap();
    assert_eq!(parts.len(), 2);
    assert_eq!(
        select_parts(&p, &parts, Some("assembly"))
            .unwrap()
            .triangles
            .len(),
        2
    );
    let b = select_parts(&p, &parts, Some("part_b")).unwrap();
    assert_eq!(b.triangles.len(), 1);
    assert!(b.positions.iter().all(|q| q.z == 3.0));
}

/// A 4 × 4 mm square in z = 0 (two triangles, facing +z) as ASCII STL, with
/// the second facet's stored normal pointing the wrong way.
const SQUARE_ASCII: &str = "solid square
facet normal 0 0 1
 outer loop
  vertex -2 -2 0
  vertex 2 -2 0
  vertex 2 2 0
 endloop
endfacet
facet normal 0 0 -1
 outer loop
  vertex -2 -2 0
  vertex 2 2 0
  vertex -2 2 0
 endloop
endfacet
endsolid square
";

/// The same square as binary STL: 80-byte header, u32 count, then per
/// triangle 12 little-endian f32 (normal, three vertices) and 2 bytes.
fn square_binary() -> Vec<u8> {
    let mut b = vec![b' '; 80];
    b.extend(2u32.to_le_bytes());
    let tris: [[f32; 12]; 2] = [
        [0., 0., 1., -2., -2., 0., 2., -2., 0., 2., 2., 0.],
        [0., 0., -1., -2., -2., 0., 2., 2., 0., -2., 2., 0.],
    ];
    for t in tris {
        for v in t {
            b.extend(v.to_le_bytes());
        }
        b.extend([0u8, 0u8]);
    }
    b
}

#[test]
fn stl_binary_and_ascii_read_as_the_same_mesh_and_shade_a_beam_by_their_area() {
    let dir = tempfile::tempdir().unwrap();
    let ascii = crate::common::write(dir.path(), "square.stl", SQUARE_ASCII);
    let binary = dir.path().join("square_bin.stl");
    std::fs::write(&binary, square_binary()).unwrap();
    let (a, report) = load(&ascii).unwrap();
    let (b, _) = load(&binary).unwrap();
    assert_eq!(a.triangles.len(), 2);
    assert_eq!(a.positions.len(), 4, "identical vertices merged");
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.triangles, b.triangles);
    let notes = report.warnings().join("\n");
    assert!(
        notes.contains("no units") && notes.contains("read as mm"),
        "{notes}"
    );
    assert!(
        notes.contains("1 of 2 triangles store a facet normal pointing against"),
        "{notes}"
    );
    // Vertex order counter-clockwise seen from +z: the front faces +z.
    let [i, j, k] = a.triangles[0].map(|i| a.positions[i as usize]);
    assert!((j - i).cross(k - i).z > 0.0);
    // A parallel beam of radius 5 mm onto a sensor, with the square as an
    // absorber in between: the sensor loses the square's share of the beam,
    // 16 / (25π) = 20.37 %; 200 000 photons: σ = 0.09 %, the test allows 0.5 %.
    let scene = "[materials.det]\ntype = \"sensor\"\nsize = [14.0, 14.0]\npixels = [14, 14]\n\n[[sources]]\ntype = \"parallel\"\ndirection = [0, 0, -1]\naperture = { center = [0, 0, 10], radius = 5.0 }\nenergy = { line = 3.0 }\n\n[[objects]]\nname = \"det\"\nmaterial = \"det\"\nshape = { type = \"rectangle\", size = [14.0, 14.0] }\n\n[[objects]]\nname = \"blocker\"\nmaterial = \"absorber\"\nshape = { type = \"mesh\", file = \"FILE\" }\ntransform = [ { translate = [0, 0, 5] } ]\n";
    for file in ["square.stl", "square_bin.stl"] {
        let s = crate::common::scene_in(dir.path(), &scene.replace("FILE", file));
        let r = traxer::trace::run(&s, &traxer::trace::RunConfig::new(200_000, 3)).unwrap();
        let reached = r.images[0].total_counts() as f64 / 200_000.0;
        let expected = 1.0 - 16.0 / (25.0 * std::f64::consts::PI);
        assert!(
            (reached - expected).abs() < 0.005,
            "{file}: {reached} vs {expected}"
        );
    }
}

#[test]
fn broken_stl_files_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let mut cut = square_binary();
    cut.truncate(120);
    let p = dir.path().join("cut.stl");
    std::fs::write(&p, &cut).unwrap();
    let e = load(&p).unwrap_err().to_string();
    assert!(
        e.contains("cut.stl") && e.contains("cut off") && e.contains("2 triangles"),
        "{e}"
    );
    // A header that counts one triangle of the two the file holds: not read
    // up to the count without a word (issue 59).
    let mut under = square_binary();
    under[80..84].copy_from_slice(&1u32.to_le_bytes());
    let p = dir.path().join("under.stl");
    std::fs::write(&p, &under).unwrap();
    let e = load(&p).unwrap_err().to_string();
    assert!(
        e.contains("under.stl") && e.contains("counts 1 triangles") && e.contains("(2 triangles)"),
        "{e}"
    );
    let p = crate::common::write(
        dir.path(),
        "bad.stl",
        "solid x\nfacet normal 0 0 1\n outer loop\n  vertex 1 2\n",
    );
    let e = load(&p).unwrap_err().to_string();
    assert!(
        e.contains("bad.stl") && e.contains("not a valid ASCII STL"),
        "{e}"
    );
    let p = dir.path().join("tiny.stl");
    std::fs::write(&p, [1u8, 2, 3]).unwrap();
    let e = load(&p).unwrap_err().to_string();
    assert!(e.contains("is not an STL file"), "{e}");
    // Only degenerate triangles: the mesh check every format shares.
    let flat = "solid f\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 2 0 0\n endloop\nendfacet\nendsolid f\n";
    let p = crate::common::write(dir.path(), "flat.stl", flat);
    let e = load(&p).unwrap_err().to_string();
    assert!(e.contains("flat.stl") && e.contains("area"), "{e}");
}
