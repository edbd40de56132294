//! Bevy's mesh instances as hroc's objects: each entity with a `Mesh3d`
//! is one object, its world box Bevy's `Aabb` × `GlobalTransform`. The
//! culler lives in the render world, on Bevy's device; its objects follow
//! the spawns, despawns and motion Bevy's change detection reports, and a
//! buffer maps Bevy's input index of each instance (what its
//! preprocessing shader sees) to the object's slot.

use bevy_camera::primitives::Aabb;
use bevy_ecs::prelude::*;
use bevy_mesh::morph::MeshMorphWeights;
use bevy_mesh::skinning::SkinnedMesh;
use bevy_mesh::Mesh3d;
use bevy_pbr::RenderMeshInstances;
use bevy_platform::collections::HashMap;
use bevy_render::mesh::{RenderMesh, RenderMeshBufferInfo};
use bevy_render::render_asset::RenderAssets;
use bevy_render::renderer::{RenderDevice, RenderQueue};
use bevy_render::sync_world::MainEntity;
use bevy_render::Extract;
use bevy_transform::components::GlobalTransform;
use hroc::device::{Capabilities, Marks};
use hroc::{Aabb as Box3, Culler, CullerDesc, ObjectDesc, ObjectFlags};

/// The mesh instances that changed since the last extraction: new or
/// moved (world box, and whether Bevy deforms the mesh on the GPU:
/// skinned, morphed), and despawned or no longer meshes.
#[derive(Resource, Default)]
pub struct ExtractedInstances {
    pub changed: HashMap<MainEntity, (Box3, bool)>,
    pub removed: Vec<MainEntity>,
}

/// World box of a local `Aabb` under `transform`.
fn world_box(aabb: &Aabb, transform: &GlobalTransform) -> Box3 {
    let m = transform.affine();
    let c = m.transform_point3a(aabb.center);
    let h = aabb.half_extents;
    let (x, y, z) = (m.matrix3.x_axis.abs(), m.matrix3.y_axis.abs(), m.matrix3.z_axis.abs());
    let e = x * h.x + y * h.y + z * h.z;
    let (lo, hi) = ((c - e).to_array(), (c + e).to_array());
    Box3::new(glam::Vec3::from_array(lo), glam::Vec3::from_array(hi))
}

/// What extraction reads of a mesh entity.
type MeshItem<'a> = (Entity, &'a Aabb, &'a GlobalTransform, Has<SkinnedMesh>, Has<MeshMorphWeights>);
/// The mesh entities whose box or deformation may have changed (a mesh
/// that stops being skinned stays never culled: only speed is lost).
type MeshChanged = (With<Mesh3d>, Or<(Changed<GlobalTransform>, Changed<Aabb>, Added<Mesh3d>, Added<SkinnedMesh>, Added<MeshMorphWeights>)>);

/// Extract: the world box and deformation of every mesh entity that
/// changed, and the entities that lost their mesh or were despawned.
pub fn extract(mut out: ResMut<ExtractedInstances>, meshes: Extract<Query<MeshItem, MeshChanged>>, mut removed: Extract<RemovedComponents<Mesh3d>>) {
    let out = &mut *out;
    // Extraction runs each frame; what the render world has not taken
    // (no culler yet) stays.
    out.removed.extend(removed.read().map(MainEntity::from));
    for e in &out.removed {
        out.changed.remove(e);
    }
    for (e, aabb, transform, skinned, morphed) in &meshes {
        out.changed.insert(MainEntity::from(e), (world_box(aabb, transform), skinned || morphed));
    }
}

/// The render world's culler and the map from Bevy's instances to its
/// objects.
#[derive(Resource, Default)]
pub struct HrocObjects {
    pub culler: Option<Culler>,
    /// Per entity: its object's slot and the box it was given.
    slots: HashMap<MainEntity, (u32, Box3, bool)>,
    /// Per Bevy input index: the object's slot, or `u32::MAX`.
    slot_of_input: Vec<u32>,
    /// `slot_of_input` on the GPU, grown as needed.
    pub slot_buffer: Option<wgpu::Buffer>,
    /// The last error, reported once.
    pub failed: Option<String>,
    /// Frames the culler waited for Bevy's meshes.
    waited: u32,
}

/// Frames the culler waits for Bevy to have every instance's mesh on the
/// GPU (which takes a few where a scene's meshes exceed Bevy's upload
/// budget of a frame); after them, an instance without one is an object
/// of one triangle.
const FIRST_WAIT: u32 = 16;

impl HrocObjects {
    /// The entity whose object has slot `slot`.
    pub fn entity_of(&self, slot: u32) -> Option<Entity> {
        self.slots.iter().find(|(_, &(s, ..))| s == slot).map(|(e, _)| e.id())
    }
}

/// Slots reserved beyond the instances at creation (the culler doubles
/// them when instances outgrow them, and its views start over).
fn capacity_for(n: usize) -> u32 {
    (n as u32 * 2).max(1024)
}

/// `triangles`: the mesh's, for what HROC's gate measures culling saves
/// (`hroc::MethodOptions::hroc_frustum_triangles`); at least 1 (an
/// instance whose mesh Bevy did not have yet when it became an object).
fn desc(b: Box3, deformed: bool, triangles: u32) -> ObjectDesc {
    // The engine draws its own meshes: the command is a placeholder the
    // stepwise frame only reads the object index and size of.
    let flags = if deformed { ObjectFlags::NEVER_CULL } else { ObjectFlags::NONE };
    ObjectDesc { bounds: b, index_count: 3 * triangles.max(1), first_index: 0, base_vertex: 0, flags, oriented: None }
}

/// Triangles of a mesh instance's mesh, once Bevy has it on the GPU (0
/// before).
fn triangles(instances: &RenderMeshInstances, meshes: &RenderAssets<RenderMesh>, entity: MainEntity) -> u32 {
    let Some(mesh) = instances.render_mesh_queue_data(entity).and_then(|data| meshes.get(data.mesh_asset_id())) else { return 0 };
    match mesh.buffer_info {
        RenderMeshBufferInfo::Indexed { count, .. } => count / 3,
        RenderMeshBufferInfo::NonIndexed => mesh.vertex_count / 3,
    }
}

/// Render world, after Bevy prepared its mesh instances: objects added,
/// removed and moved, and the input-index map uploaded.
pub fn sync(
    mut objects: ResMut<HrocObjects>,
    mut extracted: ResMut<ExtractedInstances>,
    instances: Res<RenderMeshInstances>,
    meshes: Res<RenderAssets<RenderMesh>>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    validation: Option<Res<crate::HrocValidation>>,
) {
    let objects = &mut *objects;
    let triangles = |e: MainEntity| triangles(&instances, &meshes, e);
    // The culler is made once Bevy has every instance's mesh on the GPU
    // (for their triangles), or after FIRST_WAIT frames: until then
    // nothing is culled.
    if objects.culler.is_none() && objects.waited < FIRST_WAIT && extracted.changed.keys().any(|&e| triangles(e) == 0) {
        objects.waited += 1;
        return;
    }
    let changes = std::mem::take(&mut *extracted);
    // Until the culler exists, the changes are every instance: kept for
    // the next try if it cannot be made.
    let first = objects.culler.is_none().then(|| ExtractedInstances { changed: changes.changed.clone(), removed: Vec::new() });
    let validation = validation.map_or(crate::HrocValidation::default(), |v| *v).0;
    if let Err(e) = sync_objects(objects, changes, &triangles, (&device, &queue), validation) {
        if let Some(first) = first.filter(|_| objects.culler.is_none()) {
            *extracted = first;
        }
        if objects.failed.as_deref() != Some(&e.to_string()) {
            bevy_log::error!("hroc-bevy: {e}");
            objects.failed = Some(e.to_string());
        }
        return;
    }
    // Bevy's input index of every instance, uploaded when it changed.
    let mut slot_of_input = vec![u32::MAX; objects.slot_of_input.len()];
    for (entity, &(slot, ..)) in &objects.slots {
        let Some(data) = instances.render_mesh_queue_data(*entity) else { continue };
        let input = data.current_uniform_index.0 as usize;
        if slot_of_input.len() <= input {
            slot_of_input.resize(input + 1, u32::MAX);
        }
        slot_of_input[input] = slot;
    }
    let bytes = (slot_of_input.len().max(1) * 4) as u64;
    let grown = objects.slot_buffer.as_ref().is_none_or(|b| b.size() < bytes);
    if grown {
        let size = bytes.next_power_of_two().max(4096);
        objects.slot_buffer = Some(device.wgpu_device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("hroc slot of input"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }));
    }
    if grown || slot_of_input != objects.slot_of_input {
        if let Some(b) = &objects.slot_buffer {
            let mut data = slot_of_input.clone();
            data.resize((b.size() / 4) as usize, u32::MAX);
            queue.write_buffer(b, 0, bytemuck::cast_slice(&data));
        }
        objects.slot_of_input = slot_of_input;
    }
}

fn sync_objects(
    objects: &mut HrocObjects,
    changes: ExtractedInstances,
    triangles: &dyn Fn(MainEntity) -> u32,
    (device, queue): (&RenderDevice, &RenderQueue),
    validation: bool,
) -> hroc::Result<()> {
    let ExtractedInstances { changed, removed } = changes;
    if objects.culler.is_none() {
        // The first frame: every instance.
        let entities: Vec<(MainEntity, Box3, bool)> = changed.iter().map(|(e, &(b, d))| (*e, b, d)).collect();
        let descs: Vec<ObjectDesc> = entities.iter().map(|&(e, b, d)| desc(b, d, triangles(e))).collect();
        let device = device.wgpu_device();
        let capabilities = Some(Capabilities { marks: Marks::Boxes, ..Capabilities::of(device) });
        let culler = Culler::new(device, queue, &CullerDesc { capabilities, capacity: capacity_for(descs.len()), validation, ..CullerDesc::new(&descs) })?;
        objects.slots = entities.iter().enumerate().map(|(i, &(e, b, d))| (e, (i as u32, b, d))).collect();
        objects.culler = Some(culler);
        return Ok(());
    }
    let culler = objects.culler.as_mut().expect("made above");
    // Removed (an entity may lose its mesh and get one again in a frame:
    // it is then among the changed too, and comes back as a new object).
    let gone: Vec<MainEntity> = removed.into_iter().filter(|e| objects.slots.contains_key(e)).collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    let slots: Vec<u32> = gone.iter().map(|e| objects.slots[e].0).collect();
    if !slots.is_empty() {
        culler.remove_objects(&slots)?;
    }
    for e in &gone {
        objects.slots.remove(e);
    }
    // Added, moved, and deformed or not.
    let mut added = Vec::new();
    let mut moved = Vec::new();
    let mut flags = Vec::new();
    for (e, (b, d)) in changed {
        match objects.slots.get_mut(&e) {
            None => added.push((e, b, d)),
            Some((slot, old, deformed)) => {
                if *old != b {
                    moved.push((*slot, b));
                    *old = b;
                }
                if *deformed != d {
                    flags.push((*slot, desc(b, d, 1).flags));
                    *deformed = d;
                }
            }
        }
    }
    if !added.is_empty() {
        let descs: Vec<ObjectDesc> = added.iter().map(|&(e, b, d)| desc(b, d, triangles(e))).collect();
        let slots = culler.add_objects(&descs)?;
        for (&(e, b, d), slot) in added.iter().zip(slots) {
            objects.slots.insert(e, (slot, b, d));
        }
    }
    if !moved.is_empty() {
        culler.set_bounds(&moved)?;
    }
    if !flags.is_empty() {
        culler.set_many_flags(&flags)?;
    }
    Ok(())
}
