//! `traxer tessellate`: analytic shapes → triangle meshes (glTF and/or OBJ).

use super::args::DefineArgs;
use super::InputError;
use anyhow::Context;
use std::path::PathBuf;
use traxer::geometry::{Resolution, Surface, MAX_TESSELLATION_QUADS};
use traxer::mesh::{write_mesh, write_mesh_parts, TriangleMesh};
use traxer::output::file_stem;
use traxer::scene::{analytic_shapes, inline_shape, NamedShape};

/// Tessellate analytic shapes into triangle meshes with exact vertex normals.
///
/// Either every analytic object of a scene (or those named with --object), placed
/// by its transform unless --local, or one shape given inline with --shape, e.g.
///   traxer tessellate --shape 'type="cone", radius_start=63.24, z_start=229,
///   radius_end=60.91, z_end=2, azimuth=[-15,15]' --segments 500 --rings 20 --out cone.gltf
/// --out is either one file (.gltf, .glb, .obj) that receives every shape as a
/// named part (glTF node, OBJ object; scenes pick them with `part = "NAME"`), or a
/// folder that receives NAME.<format> for each shape and format.
#[derive(clap::Args)]
pub struct TessellateArgs {
    /// Scene file whose analytic objects to tessellate.
    #[arg(required_unless_present = "shape", conflicts_with = "shape")]
    pub scene: Option<PathBuf>,
    /// One shape, written as the inside of a scene file's `shape = { ... }`.
    #[arg(value_name = "'SHAPE'", long)]
    pub shape: Option<String>,
    /// Only these objects of the scene (repeatable).
    #[arg(value_name = "NAME", long)]
    pub object: Vec<String>,
    /// Divisions around the azimuth (default: the object's `tessellate`, else 360).
    #[arg(value_name = "N", long)]
    pub segments: Option<usize>,
    /// Divisions along the axis (default: the object's `tessellate`, else 16).
    #[arg(value_name = "M", long)]
    pub rings: Option<usize>,
    /// Output file or folder.
    #[arg(value_name = "FILE|DIR", short, long)]
    pub out: PathBuf,
    /// Formats written into a folder (comma separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "gltf,obj")]
    pub format: Vec<MeshFormat>,
    /// Keep the shapes in their local frames (ignore the objects' transforms).
    #[arg(long)]
    pub local: bool,
    #[command(flatten)]
    pub vars: DefineArgs,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

/// One shape tessellated at the resolution asked (command line, else the
/// object's own, else 360 × 16), placed unless `--local`.
fn tessellate(a: &TessellateArgs, s: &NamedShape) -> Result<TriangleMesh, InputError> {
    let res = Resolution {
        segments: a
            .segments
            .or(s.resolution.map(|r| r.segments))
            .unwrap_or(360),
        rings: a.rings.or(s.resolution.map(|r| r.rings)).unwrap_or(16),
    };
    if res.segments.saturating_mul(res.rings) > MAX_TESSELLATION_QUADS {
        return Err(InputError(format!(
            "{}: {} segments × {} rings is more than {MAX_TESSELLATION_QUADS} quads",
            s.name, res.segments, res.rings
        )));
    }
    let mut mesh = s.shape.tessellate(res);
    if !a.local {
        mesh = mesh.transformed(&s.transform);
    }
    if a.quiet.quiet {
        return Ok(mesh);
    }
    say!(
        "{}: {} triangles, {} vertices ({} × {})",
        s.name,
        mesh.triangles.len(),
        mesh.positions.len(),
        res.segments,
        res.rings
    );
    Ok(mesh)
}

/// Mesh file formats `tessellate` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MeshFormat {
    Gltf,
    Glb,
    Obj,
}

impl MeshFormat {
    /// The file extension.
    fn extension(self) -> &'static str {
        match self {
            MeshFormat::Gltf => "gltf",
            MeshFormat::Glb => "glb",
            MeshFormat::Obj => "obj",
        }
    }
}

pub fn run(a: TessellateArgs) -> anyhow::Result<()> {
    if a.segments == Some(0) || a.rings == Some(0) {
        return Err(InputError("--segments and --rings must be at least 1".into()).into());
    }
    let shapes = selected_shapes(&a)?;
    let is_file = a
        .out
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ["gltf", "glb", "obj"].contains(&e.to_ascii_lowercase().as_str()));
    if is_file {
        traxer::files::check_output_file(&a.out)?;
    } else {
        let names: Vec<String> = shapes
            .iter()
            .flat_map(|s| {
                a.format
                    .iter()
                    .map(|f| format!("{}.{}", file_stem(&s.name), f.extension()))
            })
            .collect();
        traxer::files::check_output_dir(&a.out, &names)?;
        traxer::files::create_dir_all(&a.out)
            .with_context(|| format!("cannot create {}", a.out.display()))?;
    }
    let meshes = shapes
        .iter()
        .map(|s| tessellate(&a, s))
        .collect::<Result<Vec<_>, _>>()?;
    if is_file {
        // One file: one named part (glTF node, OBJ object) per shape.
        let parts: Vec<(&str, &TriangleMesh)> = shapes
            .iter()
            .map(|s| s.name.as_str())
            .zip(&meshes)
            .collect();
        write_mesh_parts(&a.out, &parts)
            .with_context(|| format!("cannot write {}", a.out.display()))?;
        let triangles: usize = meshes.iter().map(|m| m.triangles.len()).sum();
        if a.quiet.quiet {
            return Ok(());
        }
        say!(
            "wrote {} part(s), {triangles} triangles → {}",
            parts.len(),
            a.out.display()
        );
    } else {
        for (s, mesh) in shapes.iter().zip(&meshes) {
            for f in &a.format {
                let t = a
                    .out
                    .join(format!("{}.{}", file_stem(&s.name), f.extension()));
                write_mesh(&t, mesh, &s.name)
                    .with_context(|| format!("cannot write {}", t.display()))?;
                if !a.quiet.quiet {
                    say!("  → {}", t.display());
                }
            }
        }
    }
    Ok(())
}

/// The analytic shapes to tessellate: the scene's (those --object names), or
/// the one --shape.
fn selected_shapes(a: &TessellateArgs) -> anyhow::Result<Vec<NamedShape>> {
    let mut shapes: Vec<NamedShape> = match (&a.scene, &a.shape) {
        (Some(scene), _) => analytic_shapes(scene, &a.vars.define)?,
        (None, Some(text)) => vec![NamedShape {
            name: "shape".into(),
            shape: inline_shape(text)?,
            transform: Default::default(),
            resolution: None,
        }],
        (None, None) => unreachable!("clap requires one of them"),
    };
    if !a.object.is_empty() {
        for name in &a.object {
            if !shapes.iter().any(|s| &s.name == name) {
                let known: Vec<&str> = shapes.iter().map(|s| s.name.as_str()).collect();
                return Err(InputError(format!(
                    "--object {name}: no analytic object of that name (have: {known:?})"
                ))
                .into());
            }
        }
        shapes.retain(|s| a.object.contains(&s.name));
    }
    if shapes.is_empty() {
        return Err(
            InputError("nothing to tessellate: the scene has no analytic objects".into()).into(),
        );
    }
    Ok(shapes)
}
