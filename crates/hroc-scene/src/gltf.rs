//! glTF 2.0 loader (`.gltf` and `.glb`).
//!
//! The node hierarchy of the default scene is flattened into one object per
//! mesh-primitive instance; a (mesh, primitive) pair used by several nodes
//! becomes one shared [`Mesh`] (instancing), and so does a node's
//! `EXT_mesh_gpu_instancing` list of instances (one object per instance).
//! `KHR_mesh_quantization` positions and normals (8- and 16-bit integers,
//! normalized or not) are decoded to floats. Primitives are read, and
//! placed objects boxed, in parallel (rayon). A file that requires any other
//! extension the loader does not read is refused with its name.
//!
//! Files are untrusted input. The loader resolves buffers itself (only `data:`
//! URIs and relative paths inside the asset's folder), parses GLB containers
//! itself, and checks every accessor against its buffer view and buffer before
//! the `gltf` crate's reader touches it: that reader indexes and asserts on
//! out-of-range data. Nothing here may panic on a bad file.

use glam::{Mat4, Quat, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Checked;
use gltf::mesh::Mode;
use std::collections::HashMap;
use std::path::Path;

use super::{CameraPath, Mesh, Scene};
use crate::error::{Error, Result};

/// Result of checks that know the problem but not the file: the caller wraps
/// the message into `Error::Malformed`.
type Msg<T> = std::result::Result<T, String>;

/// Colour of primitives without a material.
const DEFAULT_COLOR: [f32; 3] = [0.8, 0.8, 0.8];

/// Objects a file may instance (`EXT_mesh_gpu_instancing` multiplies a
/// small file into many): every object costs the culler and the renderer.
const MAX_OBJECTS: usize = 1 << 22;

/// Extensions read here that the `gltf` crate does not know.
const READ_HERE: [&str; 2] = ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"];

/// Elements an accessor without a buffer view (all zeros, then sparse
/// substitutions) may have: such accessors cost memory that the file's size
/// does not bound.
const MAX_ZERO_FILLED: usize = 1 << 24;

pub fn load(path: &Path) -> Result<Scene> {
    let bytes = std::fs::read(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => Error::NotFound(path.to_path_buf()),
        _ => Error::Io { path: path.to_path_buf(), source: e },
    })?;
    load_bytes(&bytes, path)
}

/// Loads a `.gltf` or `.glb` file's `bytes`, read from `path`: relative
/// buffer URIs resolve inside `path`'s folder, and errors name `path`.
pub fn load_bytes(bytes: &[u8], path: &Path) -> Result<Scene> {
    let bad = |msg: String| Error::Malformed { format: "glTF", path: path.to_path_buf(), msg };

    let (json, blob) = if bytes.starts_with(b"glTF") { split_glb(bytes).map_err(bad)? } else { (bytes, None) };
    let mut root: gltf::json::Root = gltf::json::deserialize::from_slice(json).map_err(|e| bad(format!("invalid JSON: {e}")))?;
    check_position_indices(&root).map_err(bad)?;
    check_image_sources(&root).map_err(bad)?;
    check_required_extensions(&mut root).map_err(bad)?;
    let doc = gltf::Document::from_json(root).map_err(|e| bad(describe_gltf_error(&e)))?;

    let base = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    check_uris(&doc, base, path)?;
    let buffers = read_buffers(&doc, base, blob, path)?;

    // The explicit checks above and in `read_primitive` come first; this only
    // turns a reader panic we failed to foresee into an error.
    let scene = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| build_scene(&doc, &buffers, path)))
        .unwrap_or_else(|_| Err(bad("internal error while reading accessors (the file is inconsistent)".into())))?;
    Ok(scene)
}

fn build_scene(doc: &gltf::Document, buffers: &[Vec<u8>], path: &Path) -> Result<Scene> {
    let bad = |msg: String| Error::Malformed { format: "glTF", path: path.to_path_buf(), msg };
    let name = path.file_stem().map_or_else(|| "glTF".to_string(), |s| s.to_string_lossy().into_owned());
    let mut scene = Scene { name, ..Default::default() };

    let nodes: Vec<gltf::Node> = doc.nodes().collect();
    let roots: Vec<usize> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().map(|n| n.index()).collect(),
        // No scene at all: a library of nodes; show every root node.
        None => {
            let mut is_child = vec![false; nodes.len()];
            nodes.iter().flat_map(|n| n.children()).for_each(|c| is_child[c.index()] = true);
            (0..nodes.len()).filter(|&i| !is_child[i]).collect()
        }
    };

    // First the walk: every (mesh, primitive) placement, in node order, and
    // each pair once in `keys`. Reading the primitives and boxing the
    // placements come after, in parallel (rayon): they are most of a big
    // file's load time.
    let mut key_of: HashMap<(usize, usize), usize> = HashMap::new();
    let mut keys: Vec<(usize, usize)> = Vec::new();
    let mut placements: Vec<(usize, Mat4, [f32; 3])> = Vec::new();
    let mut visited = vec![false; nodes.len()];
    // Iterative depth-first walk: deep hierarchies must not overflow the stack.
    let mut stack: Vec<(usize, Mat4)> = roots.iter().rev().map(|&r| (r, Mat4::IDENTITY)).collect();
    while let Some((ni, parent)) = stack.pop() {
        // A node reached twice means a cycle or shared subtree, both invalid;
        // following it could loop forever or blow up exponentially.
        if std::mem::replace(&mut visited[ni], true) {
            return Err(bad(format!("node {ni} is reached twice (a cycle, or a node with two parents)")));
        }
        let node = &nodes[ni];
        let world = parent * local_transform(node).map_err(|m| bad(format!("node {ni}{}: {m}", node_name(node))))?;
        if !world.is_finite() {
            return Err(bad(format!("node {ni}{}: non-finite world transform", node_name(node))));
        }
        if let Some(mesh) = node.mesh() {
            let instances = gpu_instances(doc, node, buffers).map_err(|m| bad(format!("node {ni}{}: EXT_mesh_gpu_instancing: {m}", node_name(node))))?;
            for prim in mesh.primitives() {
                let key = (mesh.index(), prim.index());
                let k = *key_of.entry(key).or_insert_with(|| {
                    keys.push(key);
                    keys.len() - 1
                });
                if placements.len() + instances.len() > MAX_OBJECTS {
                    return Err(bad(format!("more than {MAX_OBJECTS} objects (mesh instances)")));
                }
                placements.extend(instances.iter().map(|t| (k, world * *t, primitive_color(&prim))));
            }
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c.index(), world));
        }
    }

    // Each used primitive once, in parallel; the first error in file order wins.
    use rayon::prelude::*;
    let meshes: Vec<gltf::Mesh> = doc.meshes().collect();
    let read: Vec<Msg<Option<Mesh>>> = keys
        .par_iter()
        .map(|&(m, p)| {
            let mesh = &meshes[m];
            let prim = mesh.primitives().nth(p).ok_or_else(|| format!("mesh {m} has no primitive {p}"))?;
            read_primitive(mesh, &prim, buffers)
        })
        .collect();
    // Key -> index into scene.meshes, or None when skipped (points, lines).
    let mut mesh_index: Vec<Option<u32>> = Vec::with_capacity(keys.len());
    for r in read {
        mesh_index.push(match r.map_err(bad)? {
            Some(m) => {
                scene.meshes.push(m);
                Some(scene.meshes.len() as u32 - 1)
            }
            None => None,
        });
    }
    let meshes = &scene.meshes;
    scene.objects = placements
        .par_iter()
        .filter_map(|&(k, transform, color)| {
            let mesh = mesh_index[k]?;
            let bounds = meshes[mesh as usize].world_bounds(&transform);
            Some(crate::Object { mesh, cluster: None, transform, color, bounds })
        })
        .collect();

    scene.validate()?;
    scene.path = CameraPath::orbit(&scene.bounds());
    Ok(scene)
}

fn node_name(node: &gltf::Node) -> String {
    node.name().map_or_else(String::new, |n| format!(" ('{n}')"))
}

/// The node's local matrix; quaternions are renormalised (exporters often
/// write slightly non-unit ones), non-finite values are an error.
fn local_transform(node: &gltf::Node) -> Msg<Mat4> {
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = Quat::from_array(rotation);
            if !q.is_finite() || q.length() < 1e-6 {
                return Err(format!("invalid rotation quaternion {rotation:?}"));
            }
            Mat4::from_scale_rotation_translation(Vec3::from(scale), q.normalize(), Vec3::from(translation))
        }
    };
    if m.is_finite() {
        Ok(m)
    } else {
        Err("non-finite transform (matrix, translation, rotation or scale)".into())
    }
}

fn primitive_color(prim: &gltf::Primitive) -> [f32; 3] {
    let material = prim.material();
    if material.index().is_none() {
        return DEFAULT_COLOR;
    }
    let [r, g, b, _] = material.pbr_metallic_roughness().base_color_factor();
    let c = [r, g, b];
    if c.iter().all(|v| v.is_finite()) {
        c.map(|v| v.clamp(0.0, 1.0))
    } else {
        DEFAULT_COLOR
    }
}

/// Reads one primitive as a triangle list; `None` for points and lines and
/// for primitives without triangles.
fn read_primitive(mesh: &gltf::Mesh, prim: &gltf::Primitive, buffers: &[Vec<u8>]) -> Msg<Option<Mesh>> {
    let what = format!("mesh {} primitive {}", mesh.index(), prim.index());
    let mode = prim.mode();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Ok(None);
    }
    let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
        return Err(format!("{what}: no POSITION attribute"));
    };
    // Floats, or KHR_mesh_quantization's integers.
    check_type(&pos_acc, "POSITION", Dimensions::Vec3, &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16])?;
    check_accessor(&pos_acc)?;
    let normal_acc = prim.get(&gltf::Semantic::Normals);
    if let Some(acc) = &normal_acc {
        check_type(acc, "NORMAL", Dimensions::Vec3, &[DataType::F32, DataType::I8, DataType::I16])?;
        check_accessor(acc)?;
        if acc.count() != pos_acc.count() {
            return Err(format!("{what}: {} normals for {} positions", acc.count(), pos_acc.count()));
        }
    }
    if let Some(acc) = prim.indices() {
        check_type(&acc, "indices", Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32])?;
        check_accessor(&acc)?;
    }

    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
    let short = || format!("{what}: accessor data is shorter than its count");
    let positions = read_vec3(&pos_acc, buffers).ok_or_else(short)?;
    let normals = match &normal_acc {
        Some(acc) => unit_normals(read_vec3(acc, buffers).ok_or_else(short)?),
        None => None,
    };
    let vertices: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None if prim.indices().is_some() => return Err(short()),
        None => (0..positions.len() as u32).collect(),
    };

    let indices = match mode {
        Mode::Triangles if !vertices.len().is_multiple_of(3) => {
            return Err(format!("{what}: {} indices is not a multiple of 3", vertices.len()));
        }
        Mode::Triangles => vertices,
        // Alternate winding so every strip triangle faces the same way (spec 3.7.2.1).
        Mode::TriangleStrip => (0..vertices.len().saturating_sub(2))
            .flat_map(|i| if i % 2 == 0 { [vertices[i], vertices[i + 1], vertices[i + 2]] } else { [vertices[i], vertices[i + 2], vertices[i + 1]] })
            .collect(),
        _ => (1..vertices.len().saturating_sub(1)).flat_map(|i| [vertices[i], vertices[i + 1], vertices[0]]).collect(),
    };
    if indices.is_empty() {
        return Ok(None);
    }
    let name = match (mesh.name(), mesh.primitives().len()) {
        (Some(n), 1) => n.to_string(),
        (Some(n), _) => format!("{n}[{}]", prim.index()),
        (None, 1) => format!("mesh{}", mesh.index()),
        (None, _) => format!("mesh{}[{}]", mesh.index(), prim.index()),
    };
    Ok(Some(Mesh::new(name, positions, normals, indices)))
}

/// An accessor's VEC3 elements as floats: floats as they are, integers
/// (KHR_mesh_quantization) as their values, or normalized to [0, 1] or
/// [-1, 1] when the accessor says so (glTF 2.0 §3.11). `None` when the data
/// is shorter than the count.
fn read_vec3(acc: &gltf::Accessor, buffers: &[Vec<u8>]) -> Option<Vec<[f32; 3]>> {
    let n = acc.normalized();
    match acc.data_type() {
        DataType::F32 => read::<f32, _>(acc, buffers, |x| x),
        DataType::I8 => read::<i8, _>(acc, buffers, |x| if n { (x as f32 / 127.0).max(-1.0) } else { x as f32 }),
        DataType::U8 => read::<u8, _>(acc, buffers, |x| if n { x as f32 / 255.0 } else { x as f32 }),
        DataType::I16 => read::<i16, _>(acc, buffers, |x| if n { (x as f32 / 32767.0).max(-1.0) } else { x as f32 }),
        DataType::U16 => read::<u16, _>(acc, buffers, |x| if n { x as f32 / 65535.0 } else { x as f32 }),
        DataType::U32 => None,
    }
}

/// An accessor's `N`-component elements of component type `T`, each
/// component mapped to a float by `f`; `None` when the data is shorter than
/// the count (the reader handles strides and sparse substitutions).
fn read<T: gltf::accessor::Item + Copy, const N: usize>(acc: &gltf::Accessor, buffers: &[Vec<u8>], f: impl Fn(T) -> f32) -> Option<Vec<[f32; N]>>
where
    [T; N]: gltf::accessor::Item,
{
    let it = gltf::accessor::Iter::<[T; N]>::new(acc.clone(), |b: gltf::Buffer| buffers.get(b.index()).map(|d| &d[..]))?;
    let v: Vec<[f32; N]> = it.map(|e| e.map(&f)).collect();
    (v.len() == acc.count()).then_some(v)
}

/// A node's instance transforms: its `EXT_mesh_gpu_instancing` TRANSLATION,
/// ROTATION and SCALE accessors composed per instance (each missing one is
/// the identity), or the node alone.
fn gpu_instances(doc: &gltf::Document, node: &gltf::Node, buffers: &[Vec<u8>]) -> Msg<Vec<Mat4>> {
    let Some(ext) = node.extension_value("EXT_mesh_gpu_instancing") else { return Ok(vec![Mat4::IDENTITY]) };
    let attributes = ext.get("attributes").and_then(|a| a.as_object()).ok_or("no attributes object")?;
    let doc_accessor = |name: &str| -> Msg<Option<gltf::Accessor>> {
        let Some(v) = attributes.get(name) else { return Ok(None) };
        let i = v.as_u64().ok_or_else(|| format!("{name} is not an accessor index"))? as usize;
        let acc = doc.accessors().nth(i).ok_or_else(|| format!("{name} accessor {i} does not exist"))?;
        check_accessor(&acc)?;
        Ok(Some(acc))
    };
    let (t, r, s) = (doc_accessor("TRANSLATION")?, doc_accessor("ROTATION")?, doc_accessor("SCALE")?);
    let count = [&t, &r, &s].iter().filter_map(|a| a.as_ref().map(|a| a.count())).max().ok_or("no TRANSLATION, ROTATION or SCALE")?;
    if [&t, &r, &s].iter().any(|a| a.as_ref().is_some_and(|a| a.count() != count)) {
        return Err("TRANSLATION, ROTATION and SCALE differ in count".into());
    }
    if count > MAX_OBJECTS {
        return Err(format!("{count} instances (at most {MAX_OBJECTS})"));
    }
    let short = || "accessor data is shorter than its count".to_string();
    let vec3 = |a: &Option<gltf::Accessor>, name: &str, default: f32| -> Msg<Vec<[f32; 3]>> {
        match a {
            Some(a) => {
                check_type(a, name, Dimensions::Vec3, &[DataType::F32])?;
                read_vec3(a, buffers).ok_or_else(short)
            }
            None => Ok(vec![[default; 3]; count]),
        }
    };
    let translations = vec3(&t, "TRANSLATION", 0.0)?;
    let scales = vec3(&s, "SCALE", 1.0)?;
    let rotations: Vec<[f32; 4]> = match &r {
        Some(a) => {
            check_type(a, "ROTATION", Dimensions::Vec4, &[DataType::F32, DataType::I8, DataType::I16])?;
            read_quats(a, buffers).ok_or_else(short)?
        }
        None => vec![[0.0, 0.0, 0.0, 1.0]; count],
    };
    let mut out = Vec::with_capacity(count);
    for k in 0..count {
        let q = Quat::from_array(rotations[k]);
        if !q.is_finite() || q.length() < 1e-6 {
            return Err(format!("instance {k}: invalid rotation {:?}", rotations[k]));
        }
        let m = Mat4::from_scale_rotation_translation(Vec3::from(scales[k]), q.normalize(), Vec3::from(translations[k]));
        if !m.is_finite() {
            return Err(format!("instance {k}: non-finite transform"));
        }
        out.push(m);
    }
    Ok(out)
}

/// Instance rotations: floats, or normalized 8/16-bit integers (KHR_mesh_quantization).
fn read_quats(acc: &gltf::Accessor, buffers: &[Vec<u8>]) -> Option<Vec<[f32; 4]>> {
    match acc.data_type() {
        DataType::F32 => read::<f32, _>(acc, buffers, |x| x),
        DataType::I8 => read::<i8, _>(acc, buffers, |x| (x as f32 / 127.0).max(-1.0)),
        DataType::I16 => read::<i16, _>(acc, buffers, |x| (x as f32 / 32767.0).max(-1.0)),
        _ => None,
    }
}

/// Refuses files that require an extension nobody here reads (Draco,
/// meshopt compression, ...), by name; lets through the ones read here,
/// which the `gltf` crate would refuse.
fn check_required_extensions(root: &mut gltf::json::Root) -> Msg<()> {
    let known = |e: &str| READ_HERE.contains(&e) || gltf::json::extensions::ENABLED_EXTENSIONS.contains(&e);
    if let Some(e) = root.extensions_required.iter().find(|e| !known(e)) {
        return Err(format!("the file requires the extension {e}, which hroc does not read (it reads {})", READ_HERE.join(", ")));
    }
    root.extensions_required.retain(|e| !READ_HERE.contains(&e.as_str()));
    Ok(())
}

/// File normals normalised, or `None` (compute them) when any is degenerate.
pub(super) fn unit_normals(normals: Vec<[f32; 3]>) -> Option<Vec<[f32; 3]>> {
    normals.into_iter().map(|n| Vec3::from(n).try_normalize().map(|v| v.to_array())).collect()
}

/// The reader decodes with the Rust type the attribute is supposed to have,
/// so any other accessor type would make it misread or panic.
fn check_type(acc: &gltf::Accessor, semantic: &str, dims: Dimensions, types: &[DataType]) -> Msg<()> {
    if acc.dimensions() != dims || !types.contains(&acc.data_type()) {
        return Err(format!("accessor {}: {semantic} must be {dims:?} of {types:?}, found {:?} of {:?}", acc.index(), acc.dimensions(), acc.data_type()));
    }
    Ok(())
}

/// Checks that every byte the reader will touch lies inside the accessor's
/// buffer views, and those inside their buffers (sparse parts included).
fn check_accessor(acc: &gltf::Accessor) -> Msg<()> {
    let (ai, count, elem) = (acc.index(), acc.count(), acc.size());
    if count == 0 {
        return Err(format!("accessor {ai}: count is 0"));
    }
    match acc.view() {
        Some(view) => check_span(&format!("accessor {ai}"), &view, acc.offset(), count, elem)?,
        None if count > MAX_ZERO_FILLED => {
            return Err(format!("accessor {ai}: {count} elements without a buffer view (at most {MAX_ZERO_FILLED})"));
        }
        None => {}
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!("accessor {ai}: sparse count {n} outside 1..={count}"));
        }
        let (indices, values) = (sparse.indices(), sparse.values());
        check_span(&format!("accessor {ai} sparse indices"), &indices.view(), indices.offset(), n, indices.index_type().size())?;
        check_span(&format!("accessor {ai} sparse values"), &values.view(), values.offset(), n, elem)?;
    }
    Ok(())
}

fn check_span(what: &str, view: &gltf::buffer::View, offset: usize, count: usize, elem: usize) -> Msg<()> {
    let (vi, buffer) = (view.index(), view.buffer());
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > buffer.length()) {
        return Err(format!("buffer view {vi}: {} bytes at offset {} exceed buffer {} ({} bytes)", view.length(), view.offset(), buffer.index(), buffer.length()));
    }
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!("{what}: buffer view {vi} stride {stride} is smaller than the {elem}-byte element"));
    }
    let end = stride.checked_mul(count - 1).and_then(|s| s.checked_add(elem)).and_then(|s| s.checked_add(offset));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!("{what}: {count} elements of {elem} bytes at offset {offset} exceed buffer view {vi} ({} bytes)", view.length()));
    }
    Ok(())
}

/// `gltf`'s validation indexes the POSITION accessor without a bounds check;
/// reject an out-of-range one before validating.
fn check_position_indices(root: &gltf::json::Root) -> Msg<()> {
    let key = Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            if let Some(a) = prim.attributes.get(&key) {
                if a.value() >= root.accessors.len() {
                    return Err(format!("mesh {mi} primitive {pi}: POSITION accessor {} does not exist ({} accessors)", a.value(), root.accessors.len()));
                }
            }
        }
    }
    Ok(())
}

/// `gltf`'s `Image::source` unwraps a URI, or a MIME type beside a buffer
/// view, that validation does not require; reject an image without one.
fn check_image_sources(root: &gltf::json::Root) -> Msg<()> {
    for (i, image) in root.images.iter().enumerate() {
        let ok = match image.buffer_view {
            Some(_) => image.mime_type.is_some(),
            None => image.uri.is_some(),
        };
        if !ok {
            return Err(format!("image {i} has neither a URI nor a buffer view with a MIME type"));
        }
    }
    Ok(())
}

fn describe_gltf_error(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => {
            let shown: Vec<String> = errors.iter().take(3).map(|(p, e)| format!("{p}: {e}")).collect();
            let more = if errors.len() > 3 { format!(" (and {} more)", errors.len() - 3) } else { String::new() };
            format!("invalid glTF: {}{more}", shown.join("; "))
        }
        e => e.to_string(),
    }
}

mod files;
use files::{check_uris, read_buffers, split_glb};
