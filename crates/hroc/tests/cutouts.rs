//! Cutout occluders (`ObjectFlags::CUTOUT`), on lavapipe: the wall across
//! the street and every fourth cube are alpha-tested (their pipeline
//! discards a checkerboard, so the street shows through the wall), drawn
//! from lists of their own without early-Z and without marks. Every method
//! family draws every object `noc` shows, on the full tier (early-Z marks:
//! the culler marks cutouts by their boxes), the portable tier (ID marks)
//! and with marks from boxes, single-sample and at MSAA 4, with validation
//! on; and cutouts occlude as other objects do (flagging every other cube
//! CUTOUT too, drawn whole by the same pipeline, culls as much).

use common::street::{look, street_on, Depth};
use glam::Vec3;
use hroc::device::{Capabilities, Marks};
use hroc::options::Variant;
use hroc::{Culler, CullerDesc, Method, ObjectFlags, ViewDesc};

mod common;

#[test]
fn cutout_objects_occlude_and_every_visible_object_is_drawn() {
    let (device, queue) = common::device(hroc::device::FULL_FEATURES);
    let mut path: Vec<(ViewDesc, bool)> = (0..4).map(|k| (look(Vec3::new(-3.0 + k as f32, 1.5, 8.0), Vec3::new(0.0, 1.0, -10.0)), false)).collect();
    path.push((look(Vec3::new(0.0, 12.0, 2.0), Vec3::new(0.0, 0.0, -12.0)), true));
    path.push((look(Vec3::new(0.0, 1.5, 2.5), Vec3::new(0.0, 1.0, -10.0)), true));
    path.push((look(Vec3::new(0.5, 1.5, 2.0), Vec3::new(0.0, 1.0, -10.0)), false));
    let tiers = [Capabilities::FULL, Capabilities::PORTABLE, Capabilities { marks: Marks::Boxes, ..Capabilities::FULL }];
    for samples in [1, 4] {
        let (host, mut objects) = street_on(&device, Depth { samples, ..Depth::default() });
        // The holed ones (the pipeline discards for every fourth object), and a never-culled cutout.
        for (i, o) in objects.iter_mut().enumerate() {
            if i % 4 == 0 || i == 1 {
                o.flags = ObjectFlags::CUTOUT;
            }
        }
        objects[1].flags = ObjectFlags::CUTOUT | ObjectFlags::NEVER_CULL;
        let mut all_cutouts = objects.clone();
        all_cutouts.iter_mut().skip(2).for_each(|o| o.flags = ObjectFlags::CUTOUT);
        let truth = Culler::new(&device, &queue, &CullerDesc::new(&objects)).unwrap();
        let visible = host.visible_along(&device, &queue, &truth, &path);
        let solid: Vec<_> = objects.iter().map(|o| hroc::ObjectDesc { flags: ObjectFlags::NONE, ..*o }).collect();
        let solid_visible = host.visible_along(&device, &queue, &Culler::new(&device, &queue, &CullerDesc::new(&solid)).unwrap(), &path);
        assert!(visible[0].len() > solid_visible[0].len(), "the wall's holes show more of the street: {} objects, {} with a solid wall", visible[0].len(), solid_visible[0].len());
        assert_eq!(visible, host.visible_along(&device, &queue, &Culler::new(&device, &queue, &CullerDesc::new(&all_cutouts)).unwrap(), &path));
        for caps in tiers {
            let culler = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&objects) }).unwrap();
            let flagged = Culler::new(&device, &queue, &CullerDesc { capabilities: Some(caps), validation: true, ..CullerDesc::new(&all_cutouts) }).unwrap();
            for method in [Method::Hzb, Method::Roc, Method::Hroc(Variant::NA), Method::HROC] {
                let label = format!("{method} with cutouts ({caps:?}, {samples} samples)");
                let mut view = culler.view(method, &host.targets()).unwrap();
                let culled = host.draws_visible_along(&device, &queue, &culler, &mut view, &path, &visible, &label);
                assert!(culled > 0, "{label} culled nothing");
                let mut view = flagged.view(method, &host.targets()).unwrap();
                let culled_flagged = host.draws_visible_along(&device, &queue, &flagged, &mut view, &path, &visible, &format!("{label}, every cube flagged"));
                assert!(culled_flagged * 10 >= culled * 9, "{label}: whole cubes flagged CUTOUT culled {culled_flagged}, as other objects {culled}");
            }
        }
    }
}
