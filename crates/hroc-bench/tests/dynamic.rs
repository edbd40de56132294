//! Dynamic scenes on lavapipe: objects that move, appear, disappear and
//! switch between static and DYNAMIC (HROC §6's hybrid), with the BVH refit
//! on the CPU and on the GPU. Every method that takes dynamic objects stays
//! at 0 false negatives and 0 missing pixels against `noc` on every frame;
//! `ioc`, which culls through the tree alone, refuses frames with objects
//! outside it. The GPU refit is checked against the CPU's.

use glam::{Mat4, Vec3};
use hroc::options::{MotionOptions, Refit};
use hroc::{Aabb, Culler, CullerDesc, ObjectDesc, ObjectFlags};
use hroc_bench::bench::{Session, Truth};
use hroc_bench::bvh::Split;
use hroc_bench::gpu::Headless;
use std::sync::OnceLock;

const RES: (u32, u32) = (160, 96);
const FRAMES: usize = 24;
const METHODS: [&str; 7] = ["vfc", "roc", "roc-all", "hzb", "hroc", "hroc-na", "hroc-cr"];

fn gpu() -> &'static Headless {
    static GPU: OnceLock<Headless> = OnceLock::new();
    GPU.get_or_init(|| Headless::new().expect("a Vulkan adapter (lavapipe: apt-get install mesa-vulkan-drivers)"))
}

/// The visible object owning most pixels.
fn largest(t: &Truth) -> u32 {
    let mut px = std::collections::HashMap::<u32, usize>::new();
    for &id in t.ids.iter().filter(|&&id| id != 0) {
        *px.entry(id - 1).or_default() += 1;
    }
    px.into_iter().max_by_key(|&(o, n)| (n, std::cmp::Reverse(o))).map(|(o, _)| o).expect("something is visible")
}

/// A transform `dist` metres ahead of camera k, `side` metres to its
/// right, turned so that the object gets an oriented box.
fn ahead(s: &Session, k: usize, dist: f32, side: f32) -> Mat4 {
    let c = s.cameras[k];
    let fwd = (c.target - c.eye).normalize();
    let right = fwd.cross(c.up).normalize();
    let turn = Mat4::from_rotation_y(0.4 + 0.3 * k as f32) * Mat4::from_rotation_x(0.3);
    Mat4::from_translation(c.eye + fwd * dist + right * side - Vec3::Y * 0.5) * turn * Mat4::from_scale(Vec3::splat(0.4))
}

/// One scripted walk through every change a host makes, run with the
/// refit on `refit`:
/// - frames 1–6: the largest occluder of frame 0 slides away;
/// - frames 2–9: an object hidden at frame 0 comes out from behind the
///   others to 15 m ahead of the camera;
/// - frame 8: an object teleports in front of the camera;
/// - frame 10: an object removed at frame 0 appears in the middle of the view;
/// - frame 12: the largest visible object of frame 11 is removed;
/// - frames 14–19: a seventh of the objects turn DYNAMIC and move, and the
///   tree is rebuilt without them at frame 15;
/// - frames 20–23: they turn static again, outside the tree until a
///   rebuild, and keep moving.
fn scripted_walk(refit: Refit, hroc_rounds: u32) {
    let scene = hroc_bench::scene::load("radial-city", Some(1500), 4).unwrap();
    let base: Vec<Mat4> = scene.objects.iter().map(|o| o.transform).collect();
    let mut s = Session::new(gpu(), scene, None, FRAMES, RES, Split::Sah).unwrap();
    s.options.hroc_rounds = hroc_rounds;
    // Objects outside the tree stay there: the hybrid path is what is tested.
    s.culler.set_motion(MotionOptions { refit, rebuild_sah_growth: f64::INFINITY, rebuild_outside: 1.0 }).unwrap();
    let mut views: Vec<hroc::View> = METHODS.iter().map(|m| s.create(m.parse().unwrap()).unwrap()).collect();
    let mut ioc = s.create("ioc".parse().unwrap()).unwrap();
    let n = s.renderer.object_count;
    let dynamic: Vec<u32> = (3..n).step_by(7).collect();
    let (_, t0) = s.truth(0).unwrap();
    let occluder = largest(&t0);
    let hidden = (0..n).rev().find(|o| !t0.visible.contains(o) && *o != occluder && !dynamic.contains(o) && o % 7 != 3).unwrap();
    let (teleport, appear) = (11u32, 23u32);
    s.remove_objects(&[appear]).unwrap();
    let (mut removed, mut seen_hidden, mut drawn) = (None, false, 0usize);
    for k in 0..FRAMES {
        let mut moves = Vec::new();
        if (1..=6).contains(&k) {
            moves.push((occluder, Mat4::from_translation(Vec3::new(5.0 * k as f32, 0.0, 3.0 * k as f32)) * base[occluder as usize]));
        }
        if (2..=9).contains(&k) {
            // From its place to 15 m ahead of the camera, in eight steps.
            let to = ahead(&s, k, 15.0, 0.0).w_axis.truncate() - base[hidden as usize].w_axis.truncate();
            moves.push((hidden, Mat4::from_translation(to * (k - 1) as f32 / 8.0) * base[hidden as usize]));
        }
        if k == 8 {
            moves.push((teleport, ahead(&s, k, 9.0, 0.0)));
        }
        if (16..=19).contains(&k) {
            // Turning in place: its oriented box follows it.
            moves.push((teleport, ahead(&s, 8, 9.0, 0.0) * Mat4::from_rotation_z(0.5 * k as f32)));
        }
        if k >= 14 {
            moves.extend(dynamic.iter().map(|&i| (i, Mat4::from_translation(Vec3::new(10.0 * (k as f32 * 0.5 + i as f32).sin(), 0.0, 8.0)) * base[i as usize])));
        }
        if k == 14 {
            for &i in dynamic.iter().filter(|&&i| Some(i) != removed) {
                s.set_flags(i, ObjectFlags::DYNAMIC).unwrap();
            }
        }
        if k == 20 {
            for &i in dynamic.iter().filter(|&&i| Some(i) != removed) {
                s.set_flags(i, ObjectFlags::NONE).unwrap();
            }
        }
        moves.retain(|m| Some(m.0) != removed);
        s.move_objects(&moves).unwrap();
        if k == 15 {
            s.culler.rebuild().unwrap();
            assert!(dynamic.iter().all(|&i| s.bvh().leaf_of_object[i as usize] == hroc::bvh::NO_LEAF), "DYNAMIC objects stay out of a rebuilt tree");
        }
        if k == 10 {
            s.add_objects(&[(appear, ahead(&s, k, 8.0, 0.5))]).unwrap();
            assert!(s.culler.oriented(appear).is_some(), "an object added turned has an oriented box");
        }
        if k == 8 {
            assert!(s.culler.oriented(teleport).is_some(), "a moved object that turned has an oriented box");
        }
        if k == 12 {
            let (_, t11) = s.truth(11).unwrap();
            let gone = largest(&t11);
            s.remove_objects(&[gone]).unwrap();
            removed = Some(gone);
        }
        let (_, truth) = s.truth(k).unwrap();
        seen_hidden |= truth.visible.contains(&hidden);
        match k {
            8 => assert!(truth.visible.contains(&teleport), "the teleported object is in view"),
            10 => assert!(truth.visible.contains(&appear), "the added object is in view"),
            _ => {}
        }
        if let Some(g) = removed {
            assert!(!truth.visible.contains(&g), "a removed object is not drawn");
        }
        for v in views.iter_mut() {
            let r = s.run_frame(v, k).unwrap();
            let c = s.check(&r, &truth).unwrap();
            assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{refit:?} {} frame {k}: missed objects/pixels", v.method());
            drawn += c.drawn;
        }
        match s.run_frame(&mut ioc, k) {
            Ok(r) if k < 14 => {
                let c = s.check(&r, &truth).unwrap();
                assert_eq!((c.false_negatives, c.missing_pixels), (0, 0), "{refit:?} ioc frame {k}");
            }
            Ok(_) => panic!("ioc culled frame {k} with objects outside its tree"),
            Err(e) => assert!(k >= 14 && e.to_string().contains("outside it"), "frame {k}: {e}"),
        }
    }
    assert!(seen_hidden, "the hidden object came out from behind");
    // Culling still happens.
    assert!(drawn < n as usize * FRAMES * METHODS.len() / 4, "drew {drawn} of {}", n as usize * FRAMES * METHODS.len());
}

#[test]
fn every_change_stays_conservative_with_cpu_refit() {
    scripted_walk(Refit::Cpu, 1);
}

#[test]
fn every_change_stays_conservative_with_gpu_refit() {
    // With HROC's front-to-back occludee rounds.
    scripted_walk(Refit::Gpu, 3);
}

fn objects(n: usize) -> Vec<ObjectDesc> {
    (0..n)
        .map(|i| {
            let c = Vec3::new((i % 17) as f32 * 3.0, (i % 5) as f32, (i / 17) as f32 * 3.0);
            ObjectDesc { bounds: Aabb::new(c, c + Vec3::new(1.0, 2.0, 1.5)), index_count: 3, first_index: 0, base_vertex: 0, flags: ObjectFlags::NONE, oriented: None }
        })
        .collect()
}

/// Oriented boxes: given at creation, by `add_objects` and `set_oriented`;
/// dropped by `set_bounds` (the box moved, its own box did not), by
/// `set_bounds_gpu` and by removal. Bad ones are refused, and nothing
/// changes then.
#[test]
fn oriented_boxes_follow_their_objects() {
    let g = gpu();
    let turned = |b: Aabb| {
        let local = Aabb::new(-b.extent() * 0.5, b.extent() * 0.5);
        hroc::geometry::OrientedBox::new(local, glam::Affine3A::from_rotation_translation(glam::Quat::from_rotation_y(0.7), b.center()))
    };
    let mut objs = objects(30);
    for o in objs.iter_mut().step_by(2) {
        let ob = turned(o.bounds);
        (o.bounds, o.oriented) = (ob.world_bounds(), Some(ob));
    }
    let mut c = Culler::new(&g.device, &g.queue, &CullerDesc { capacity: 32, ..CullerDesc::new(&objs) }).unwrap();
    assert_eq!(c.oriented(4), objs[4].oriented);
    assert_eq!(c.oriented(5), None);
    c.set_bounds(&[(4, moved(objs[4].bounds, 4))]).unwrap();
    assert_eq!(c.oriented(4), None, "set_bounds drops the old oriented box");
    c.set_oriented(&[(4, objs[4].oriented), (5, Some(turned(objs[5].bounds)))]).unwrap();
    assert!(c.oriented(4).is_some() && c.oriented(5).is_some());
    let flat = hroc::geometry::OrientedBox::new(Aabb::new(Vec3::ZERO, Vec3::ONE), glam::Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)));
    let e = c.set_oriented(&[(9, Some(turned(objs[9].bounds))), (7, Some(flat))]).unwrap_err().to_string();
    assert!(e.contains("object 7") && e.contains("invertible"), "{e}");
    assert_eq!(c.oriented(9), None, "nothing changes on an error");
    let e = Culler::new(&g.device, &g.queue, &CullerDesc::new(&[ObjectDesc { oriented: Some(flat), ..objs[0] }])).err().expect("a flat box is refused").to_string();
    assert!(e.contains("invertible"), "{e}");
    c.remove_objects(&[4]).unwrap();
    assert_eq!(c.oriented(4), None);
    assert!(c.set_oriented(&[(4, objs[4].oriented)]).unwrap_err().to_string().contains("removed"));
    let id = c.add_objects(&objs[2..3]).unwrap()[0];
    assert_eq!(c.oriented(id), objs[2].oriented);
    // Past the capacity: new buffers, and every kept box goes up again.
    let grown = c.add_objects(&objs[10..16]).unwrap();
    assert_eq!(c.object_count(), 64);
    assert_eq!(grown.iter().map(|&i| c.oriented(i)).collect::<Vec<_>>(), objs[10..16].iter().map(|o| o.oriented).collect::<Vec<_>>());
    let on_gpu = c.read_oriented().unwrap();
    assert_eq!(on_gpu.len(), 64);
    for (i, g) in on_gpu.iter().enumerate() {
        assert_eq!(g.valid == 1, c.oriented(i as u32).is_some(), "slot {i}: the GPU's oriented box after growing");
    }
    assert!(on_gpu[0].valid == 1 && on_gpu[5].valid == 1 && on_gpu[id as usize].valid == 1);
    use wgpu::util::DeviceExt;
    let host: Vec<[f32; 8]> = (0..64).map(|i| [i as f32, 0.0, 0.0, 0.0, i as f32 + 1.0, 1.0, 1.0, 0.0]).collect();
    let buf = g.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: None, contents: bytemuck::cast_slice(&host), usage: wgpu::BufferUsages::STORAGE });
    let mut enc = g.device.create_command_encoder(&Default::default());
    c.set_bounds_gpu(&mut enc, &buf).unwrap();
    g.queue.submit([enc.finish()]);
    assert!((0..64).all(|i| c.oriented(i).is_none()), "set_bounds_gpu drops every oriented box");
    assert!(c.read_oriented().unwrap().iter().all(|g| g.valid == 0), "and on the GPU");
}

fn moved(b: Aabb, i: usize) -> Aabb {
    let d = Vec3::new((i as f32).sin() * 9.0, (i as f32 * 0.3).cos() * 4.0, -(i as f32).cos() * 7.0);
    Aabb::new(b.min + d, b.max + d)
}

/// The GPU refit (from uploaded boxes, and from a host buffer) gives the
/// CPU refit's nodes exactly: min and max are exact in any order. A box
/// that is not finite becomes one around everything.
#[test]
fn gpu_refit_matches_cpu_refit() {
    let g = gpu();
    let objs = objects(700);
    let mut cpu = Culler::new(&g.device, &g.queue, &CullerDesc::new(&objs)).unwrap();
    let desc = CullerDesc { motion: MotionOptions { refit: Refit::Gpu, rebuild_sah_growth: f64::INFINITY, ..Default::default() }, ..CullerDesc::new(&objs) };
    let mut on_gpu = Culler::new(&g.device, &g.queue, &desc).unwrap();
    let moves: Vec<(u32, Aabb)> = (0..objs.len()).step_by(3).map(|i| (i as u32, moved(objs[i].bounds, i))).collect();
    cpu.set_bounds(&moves).unwrap();
    on_gpu.set_bounds(&moves).unwrap();
    assert_eq!(on_gpu.read_nodes().unwrap(), cpu.bvh().nodes, "GPU refit from uploaded boxes");
    let mut boxes: Vec<Aabb> = objs.iter().map(|o| o.bounds).collect();
    for &(i, b) in &moves {
        boxes[i as usize] = b;
    }
    cpu.bvh().validate(&boxes).unwrap();

    // From a host buffer: every object moves again; one box is NaN.
    let mut host: Vec<[f32; 8]> = boxes.iter().enumerate().map(|(i, b)| moved(*b, i + 1)).map(|b| [b.min.x, b.min.y, b.min.z, 0.0, b.max.x, b.max.y, b.max.z, 0.0]).collect();
    host[5][1] = f32::NAN;
    use wgpu::util::DeviceExt;
    let buf = g.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: None, contents: bytemuck::cast_slice(&host), usage: wgpu::BufferUsages::STORAGE });
    let mut enc = g.device.create_command_encoder(&Default::default());
    on_gpu.set_bounds_gpu(&mut enc, &buf).unwrap();
    g.queue.submit([enc.finish()]);
    let want: Vec<(u32, Aabb)> = host
        .iter()
        .enumerate()
        .map(|(i, h)| (i as u32, if i == 5 { Aabb::new(Vec3::splat(-1e18), Vec3::splat(1e18)) } else { Aabb::new(Vec3::new(h[0], h[1], h[2]), Vec3::new(h[4], h[5], h[6])) }))
        .collect();
    cpu.set_bounds(&want).unwrap();
    assert_eq!(on_gpu.read_nodes().unwrap(), cpu.bvh().nodes, "GPU refit from the host's buffer");
    // The CPU takes over again after reading the GPU's boxes back.
    on_gpu.set_bounds(&[(7, objs[7].bounds)]).unwrap();
    cpu.set_bounds(&[(7, objs[7].bounds)]).unwrap();
    assert_eq!(on_gpu.read_nodes().unwrap(), cpu.bvh().nodes, "CPU changes after a GPU refit");

    let small = g.device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 64, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
    let mut enc = g.device.create_command_encoder(&Default::default());
    let e = on_gpu.set_bounds_gpu(&mut enc, &small).expect_err("too small").to_string();
    assert!(e.contains("needs 22400 bytes"), "{e}");
}

/// Slots: removed ones are reused lowest first; adding past the capacity
/// doubles it, and a view built before keeps working (rebuilt for the new
/// slots). The
/// policy rebuilds the tree when objects outside it, or frozen leaves in
/// it, exceed the fraction,
/// and when refits degrade it past the SAH growth.
#[test]
fn slots_capacity_and_rebuild_policy() {
    let g = gpu();
    let objs = objects(40);
    let desc = CullerDesc { capacity: 48, motion: MotionOptions { rebuild_outside: 0.1, rebuild_sah_growth: 1.5, ..Default::default() }, ..CullerDesc::new(&objs) };
    let mut c = Culler::new(&g.device, &g.queue, &desc).unwrap();
    assert_eq!(c.object_count(), 48);
    c.remove_objects(&[9, 3]).unwrap();
    assert!(!c.is_live(3) && c.flags(3).is_none());
    assert!(c.remove_objects(&[3]).unwrap_err().to_string().contains("removed"));
    assert!(c.remove_objects(&[5, 5]).unwrap_err().to_string().contains("twice"));
    assert!(c.set_bounds(&[(60, objs[0].bounds)]).unwrap_err().to_string().contains("out of range"));
    // Reused slots come back into the tree by refit; new slots stay outside.
    let ids = c.add_objects(&objs[..6]).unwrap();
    assert_eq!(ids, vec![3, 9, 40, 41, 42, 43]);
    assert!(c.bvh().leaf_of_object[3] != hroc::bvh::NO_LEAF && c.bvh().leaf_of_object[40] == hroc::bvh::NO_LEAF);
    assert!(!c.last_update().rebuilt, "4 of 44 outside is under a tenth");
    c.add_objects(&objs[..1]).unwrap();
    assert!(c.last_update().rebuilt, "5 of 45 outside is over a tenth");
    assert!(c.bvh().leaf_of_object[40] != hroc::bvh::NO_LEAF);
    // Moving a third far away degrades the tree past 1.5x: rebuilt.
    let far: Vec<(u32, Aabb)> = (0..40).step_by(3).map(|i| (i as u32, Aabb::new(objs[i].bounds.min, objs[i].bounds.max + Vec3::splat(30.0)))).collect();
    c.set_bounds(&far).unwrap();
    let u = c.last_update();
    assert!(u.rebuilt && u.sah_growth == Some(1.0), "{u:?}");
    // Frozen leaves count too: 4 objects of 45 turned DYNAMIC stay in the
    // tree, frozen; a fifth rebuilds it without them.
    let dynamic: Vec<(u32, ObjectFlags)> = (0..5).map(|i| (i, ObjectFlags::DYNAMIC)).collect();
    c.set_many_flags(&dynamic[..4]).unwrap();
    assert!(!c.last_update().rebuilt && c.bvh().leaf_of_object[0] != hroc::bvh::NO_LEAF);
    c.set_many_flags(&dynamic[4..]).unwrap();
    assert!(c.last_update().rebuilt && c.bvh().leaf_of_object[0] == hroc::bvh::NO_LEAF);

    // Past the capacity: 64 slots, and an old view still culls.
    let depth = g.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width: 32, height: 32, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let targets = hroc::ViewTargets::new(&depth, hroc::DepthRange::Standard);
    let mut view = c.view(hroc::Method::Vfc, &targets).unwrap();
    c.add_objects(&objects(10)).unwrap();
    assert_eq!(c.object_count(), 64);
    let view_desc = hroc::ViewDesc {
        view: Mat4::look_at_rh(Vec3::new(-10.0, 3.0, -10.0), Vec3::new(20.0, 0.0, 20.0), Vec3::Y),
        proj: Mat4::perspective_rh(1.0, 1.0, 0.1, 500.0),
        unclipped_depth: false,
    };
    let mut lists = 0;
    let mut enc = g.device.create_command_encoder(&Default::default());
    let input = hroc::FrameInput { view: view_desc, cut: false, time: 0.0 };
    view.cull(&c, &mut enc, &input, &mut |_: &mut wgpu::CommandEncoder, _: &hroc::Draw<'_>| lists += 1).unwrap();
    g.queue.submit([enc.finish()]);
    g.wait().unwrap();
    assert_eq!(lists, 1, "the regrown view handed over its list");
}
