//! Helpers shared by the tests.

use std::path::{Path, PathBuf};
use traxer::embree::Device;
use traxer::geometry::Surface;
use traxer::scene::Scene;

pub fn device() -> Device {
    Device::new().expect("Embree device")
}

/// Writes `text` as `name` in `dir` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Builds a scene from TOML text (files it names are relative to `dir`).
pub fn scene_in(dir: &Path, text: &str) -> Scene {
    let p = write(dir, "scene.toml", text);
    Scene::load(&device(), &p, &[]).unwrap_or_else(|e| panic!("scene should load: {e}"))
}

pub fn scene(text: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    scene_in(dir.path(), text)
}

/// The repository root (for shipped scenes and meshes).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Flux-weighted centroid and RMS radius (in pixels) of an image [iy][ix].
pub fn centroid_rms(img: &[f64], nx: usize) -> (f64, f64, f64) {
    let (mut w, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for (k, &v) in img.iter().enumerate() {
        let (x, y) = ((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        w += v;
        sx += v * x;
        sy += v * y;
    }
    let (cx, cy) = (sx / w, sy / w);
    let mut s2 = 0.0;
    for (k, &v) in img.iter().enumerate() {
        let (x, y) = ((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        s2 += v * ((x - cx).powi(2) + (y - cy).powi(2));
    }
    (cx, cy, (s2 / w).sqrt())
}

/// The flat-mirror bench used by several tests: a pencil beam (radius 0.2 mm)
/// along −z from z = 500 meets a 20 × 100 mm flat mirror at the origin at
/// `graze_deg`; a 60 × 60 mm screen lies 200 mm below. `mirror` is the mirror
/// material's table (with `type = "mirror"`), `pixels` the screen's pixels per
/// side, `sensor_extra` and `mirror_extra` extra lines for the sensor material and
/// the mirror object.
pub fn flat_mirror_bench(
    graze_deg: f64,
    mirror: &str,
    energy: &str,
    pixels: u32,
    sensor_extra: &str,
    mirror_extra: &str,
) -> String {
    format!(
        r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 500], radius = 0.2 }}
energy = {energy}

[materials.flat_mirror]
{mirror}

[materials.detector]
type = "sensor"
size = [60.0, 60.0]
pixels = [{pixels}, {pixels}]
{sensor_extra}

[[objects]]
name = "flat"
material = "flat_mirror"
shape = {{ type = "rectangle", size = [20.0, 100.0] }}
transform = [ {{ rotate = {{ axis = [1, 0, 0], angle = {angle} }} }} ]
{mirror_extra}

[[objects]]
name = "screen"
material = "detector"
shape = {{ type = "rectangle", size = [60.0, 60.0] }}
transform = [ {{ translate = [0, 0, -200] }} ]
"#,
        // Rotating the rectangle's +z normal about x by (90° − θ) makes the surface
        // meet −z rays at the grazing angle θ.
        angle = 90.0 - graze_deg
    )
}

/// The `traxer` binary built for these tests, as a command to add arguments to.
pub fn traxer() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_traxer"))
}

/// Runs a `traxer` command that must fail with exit code `code`; returns its
/// stderr (which must not hold a panic).
pub fn run_fails(cmd: &mut std::process::Command, code: i32) -> String {
    let out = cmd.output().expect("run traxer");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(code), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// Runs a `traxer` command that must succeed (stderr shown if it does not).
pub fn run_ok(cmd: &mut std::process::Command) -> std::process::Output {
    let out = cmd.output().expect("run traxer");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The error message of a scene that must fail to load.
pub fn load_error(dir: &Path, text: &str) -> String {
    let p = write(dir, "s.toml", text);
    match Scene::load(&device(), &p, &[]) {
        Ok(_) => panic!("the scene should not load"),
        Err(e) => e.to_string(),
    }
}

/// A minimal glTF with one triangle (0,0,0), (1,0,0), (0,1,0) as mesh 0 (+ optional
/// extra primitives), the given node list and one scene per entry of `scenes` (its
/// node list; the first is the default), buffer embedded as a data URI.
pub fn gltf_with_nodes(nodes: &str, scenes: &[&str], extra_primitives: &str) -> String {
    use base64::Engine;
    let mut bin = Vec::new();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let uri = base64::engine::general_purpose::STANDARD.encode(&bin);
    let scenes: Vec<String> = scenes
        .iter()
        .map(|n| format!(r#"{{"nodes":{n}}}"#))
        .collect();
    let scenes = scenes.join(",");
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{scenes}],"nodes":{nodes},
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}{extra_primitives}]}}],
"buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{uri}"}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
    )
}

/// A text replacement (from, to).
type Edit<'a> = (&'a str, &'a str);

/// Mesh files that must not import: (file name, content, words the error must
/// contain). Non-finite coordinates, indices out of range, no triangles, garbage,
/// a truncated binary glTF, broken JSON, compressed geometry.
pub fn broken_mesh_files() -> Vec<(&'static str, Vec<u8>, Vec<&'static str>)> {
    let mut files: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        ("nan.obj", b"v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n".to_vec(), vec!["non-finite"]),
        ("range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n".to_vec(), vec![]),
        ("empty.obj", b"# nothing\nv 0 0 0\n".to_vec(), vec!["no triangles"]),
        ("garbage.obj", b"v 0 zero 0\nf 1 2 3\n".to_vec(), vec!["not a valid OBJ"]),
        (
            "broken.gltf",
            b"{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ ".to_vec(),
            vec!["not valid glTF JSON"],
        ),
        (
            "draco.gltf",
            br#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],"meshes":[]}"#.to_vec(),
            vec!["requires the glTF extension KHR_draco_mesh_compression", "export the file without mesh compression"],
        ),
    ];
    // The one-triangle glTF of `gltf_with_nodes`, edited: (file, edits, words).
    let edited: [(&str, &[Edit], Vec<&str>); 6] = [
        // A LINES primitive only.
        (
            "lines.gltf",
            &[(r#""POSITION":0}}"#, r#""POSITION":0},"mode":1}"#)],
            vec!["no triangles"],
        ),
        // An accessor declaring 6 vertices in a 3-vertex buffer view (the gltf
        // crate alone would read nothing, or what fits, without complaint).
        (
            "short.gltf",
            &[(r#""count":3"#, r#""count":6"#)],
            vec!["POSITION accessor 0 declares 6 elements"],
        ),
        // The same for a NORMAL accessor (else the normals would silently be
        // computed).
        (
            "shortnormals.gltf",
            &[
                (r#""POSITION":0}"#, r#""POSITION":0,"NORMAL":1}"#),
                (
                    r#""max":[1,1,0]}]"#,
                    r#""max":[1,1,0]},{"bufferView":0,"componentType":5126,"count":6,"type":"VEC3"}]"#,
                ),
            ],
            vec!["NORMAL accessor 1 declares 6 elements"],
        ),
        // An attribute naming an accessor that does not exist: the gltf crate's
        // own validation panics on it (it indexes the accessor list first).
        (
            "noaccessor.gltf",
            &[(r#""POSITION":0}"#, r#""POSITION":4}"#)],
            vec!["malformed glTF"],
        ),
        // Indices stored as VEC3 floats (the gltf crate reaches `unreachable!()`
        // on index types glTF does not allow).
        (
            "floatindices.gltf",
            &[(r#""POSITION":0}"#, r#""POSITION":0},"indices":0"#)],
            vec!["indices accessor 0 holds Vec3 of F32", "U8 or U16 or U32"],
        ),
        // An external buffer that is not there.
        (
            "nobuffer.gltf",
            &[(r#""uri":"data:"#, r#""uri":"nothere.bin","x":"data:"#)],
            vec!["buffer 0 refers to", "nothere.bin", "does not exist"],
        ),
    ];
    for (file, edits, needles) in edited {
        let text = edits.iter().fold(
            gltf_with_nodes(r#"[{"mesh":0}]"#, &["[0]"], ""),
            |text, (from, to)| {
                assert!(text.contains(from), "{file}: nothing to edit at {from}");
                text.replace(from, to)
            },
        );
        files.push((file, text.into_bytes(), needles));
    }
    let m = traxer::geometry::Shape::Sphere(traxer::geometry::Sphere { radius: 1.0 }).tessellate(
        traxer::geometry::Resolution {
            segments: 8,
            rings: 4,
        },
    );
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("ok.glb");
    traxer::mesh::write_mesh(&glb, &m, "s").unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    files.push(("truncated.glb", bytes[..bytes.len() / 2].to_vec(), vec![]));
    // Three vertices, indices [0, 1, 7].
    let mut bin = Vec::new();
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        bin.extend_from_slice(&c.to_le_bytes());
    }
    for i in [0u32, 1, 7] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    use base64::Engine;
    let uri = base64::engine::general_purpose::STANDARD.encode(&bin);
    let bad = format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
"buffers":[{{"byteLength":48,"uri":"data:application/octet-stream;base64,{uri}"}}],
"bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":12}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
             {{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}}]}}"#
    );
    files.push((
        "badindex.gltf",
        bad.into_bytes(),
        vec!["vertex index", "only 3 vertices"],
    ));
    files
}
