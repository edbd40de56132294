//! Object BVH: structural invariants, queries against brute force, degenerate
//! and adversarial inputs, layout, and the quality ordering of the splits.

use glam::{Mat4, Vec3, Vec4};
use hroc::bvh::{Bvh, BvhNode, Split, LEAF_BIT, NO_PARENT};
use hroc::geometry::{aabb_in_frustum, frustum_planes};
use hroc::Aabb;
use proptest::prelude::*;

fn aabb(min: [f32; 3], max: [f32; 3]) -> Aabb {
    Aabb::new(Vec3::from(min), Vec3::from(max))
}

fn brute_aabb(boxes: &[Aabb], q: &Aabb) -> Vec<u32> {
    (0..boxes.len() as u32).filter(|&i| boxes[i as usize].overlaps(q)).collect()
}

fn brute_frustum(boxes: &[Aabb], planes: &[Vec4; 6]) -> Vec<u32> {
    (0..boxes.len() as u32).filter(|&i| aabb_in_frustum(planes, boxes[i as usize].min, boxes[i as usize].max)).collect()
}

/// Builds with every split and checks validate() plus the O(1) navigation.
fn build_all(boxes: &[Aabb]) -> Vec<Bvh> {
    Split::ALL
        .iter()
        .map(|&split| {
            let bvh = Bvh::build(boxes, split);
            bvh.validate(boxes).unwrap_or_else(|e| panic!("{split}: {e}"));
            check_navigation(&bvh);
            bvh
        })
        .collect()
}

/// Sibling/parent/children round trips, leaf_of_object, depth-first layout.
fn check_navigation(bvh: &Bvh) {
    let n = bvh.nodes.len() as u32;
    if n == 0 {
        assert_eq!(bvh.depth(), 0);
        return;
    }
    assert_eq!(bvh.parent(0), None);
    assert_eq!(bvh.sibling(0), None);
    assert_eq!(bvh.nodes[0].parent, NO_PARENT);
    for i in 1..n {
        let s = bvh.sibling(i).unwrap();
        assert_eq!(bvh.sibling(s), Some(i));
        let p = bvh.parent(i).unwrap();
        assert!(p < i, "parent {p} of {i} must come first");
        assert_eq!(bvh.parent(s), Some(p));
        let c = bvh.children(p).unwrap();
        assert!(c.contains(&i) && c.contains(&s));
    }
    // Leaf counts, bottom-up (children always follow parents).
    let mut leaves = vec![0u32; n as usize];
    for i in (0..n).rev() {
        leaves[i as usize] = match bvh.children(i) {
            None => 1,
            Some([l, r]) => leaves[l as usize] + leaves[r as usize],
        };
    }
    for i in 0..n {
        match (bvh.children(i), bvh.object(i)) {
            (Some([l, r]), None) => {
                assert!(!bvh.is_leaf(i));
                assert_eq!(r, l + 1);
                // Depth-first pair allocation: a subtree's nodes are one range.
                if let Some([ll, _]) = bvh.children(l) {
                    assert_eq!(ll, l + 2, "left child's pair follows the parent's pair");
                }
                if let Some([rl, _]) = bvh.children(r) {
                    assert_eq!(rl, l + 2 * leaves[l as usize], "right child's pair follows the left subtree");
                }
            }
            (None, Some(o)) => {
                assert!(bvh.is_leaf(i));
                assert_eq!(bvh.leaf_of_object[o as usize], i);
                assert_eq!(bvh.nodes[i as usize].child, LEAF_BIT | o);
            }
            other => panic!("node {i}: {other:?}"),
        }
    }
}

fn ceil_log2(n: usize) -> u32 {
    if n <= 1 {
        0
    } else {
        usize::BITS - (n - 1).leading_zeros()
    }
}

/// Deterministic pseudo-random boxes (SplitMix64).
fn random_boxes(n: usize, seed: u64, clusters: usize) -> Vec<Aabb> {
    let mut s = seed;
    let mut next = move || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut v = move || Vec3::new(next(), next(), next());
    let centres: Vec<Vec3> = (0..clusters.max(1)).map(|_| v() * 1000.0).collect();
    (0..n)
        .map(|i| {
            let c = if clusters > 0 { centres[i % clusters] + (v() - 0.5) * 20.0 } else { v() * 1000.0 };
            let h = v() * 2.0 + 0.1;
            Aabb::new(c - h, c + h)
        })
        .collect()
}

// ---------------------------------------------------------------- strategies

/// Boxes with centres in a 200³ region and half sizes up to 20 (some zero:
/// points and flat boxes), and a few repeated boxes.
fn box_set(max: usize) -> impl Strategy<Value = Vec<Aabb>> {
    let one = (prop::array::uniform3(-100.0f32..100.0), prop::array::uniform3(prop_oneof![3 => 0.0f32..20.0, 1 => Just(0.0f32)]));
    (prop::collection::vec(one, 0..max), prop::collection::vec(any::<prop::sample::Index>(), 0..8)).prop_map(|(v, dups)| {
        let mut boxes: Vec<Aabb> = v.into_iter().map(|(c, h)| Aabb::new(Vec3::from(c) - Vec3::from(h), Vec3::from(c) + Vec3::from(h))).collect();
        if !boxes.is_empty() {
            for d in dups {
                let b = boxes[d.index(boxes.len())];
                boxes.push(b);
            }
        }
        boxes
    })
}

fn query_box() -> impl Strategy<Value = Aabb> {
    (prop::array::uniform3(-120.0f32..120.0), prop::array::uniform3(0.0f32..60.0)).prop_map(|(c, h)| Aabb::new(Vec3::from(c) - Vec3::from(h), Vec3::from(c) + Vec3::from(h)))
}

/// A random perspective view-projection looking into the box region.
fn view_proj() -> impl Strategy<Value = Mat4> {
    (prop::array::uniform3(-200.0f32..200.0), prop::array::uniform3(-100.0f32..100.0), 10.0f32..120.0, 0.5f32..2.0, 0.01f32..10.0, 1.0f32..400.0).prop_filter_map(
        "degenerate camera",
        |(eye, target, fov, aspect, near, depth)| {
            let (eye, target) = (Vec3::from(eye), Vec3::from(target));
            let dir = target - eye;
            let up = if dir.normalize_or_zero().y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
            (dir.length() > 1e-3).then(|| Mat4::perspective_rh(fov.to_radians(), aspect, near, near + depth) * Mat4::look_at_rh(eye, target, up))
        },
    )
}

/// Any finite f32, with extra weight on huge, tiny and repeated values.
fn any_coord() -> impl Strategy<Value = f32> {
    use prop::num::f32::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    prop_oneof![
        4 => POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO,
        2 => -1e30f32..1e30,
        2 => -10.0f32..10.0,
        1 => Just(f32::MAX),
        1 => Just(f32::MIN),
        1 => Just(1e30f32),
        1 => Just(-1e30f32),
        1 => Just(0.0f32),
    ]
}

fn any_box() -> impl Strategy<Value = Aabb> {
    (prop::array::uniform3(any_coord()), prop::array::uniform3(any_coord())).prop_map(|(a, b)| {
        let (a, b) = (Vec3::from(a), Vec3::from(b));
        Aabb::new(a.min(b), a.max(b))
    })
}

// ---------------------------------------------------------------- proptests

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_sets_valid_and_queries_match_brute_force(
        boxes in box_set(300),
        queries in prop::collection::vec(query_box(), 4),
        cams in prop::collection::vec(view_proj(), 3),
    ) {
        for bvh in build_all(&boxes) {
            prop_assert_eq!(bvh.nodes.len(), if boxes.is_empty() { 0 } else { 2 * boxes.len() - 1 });
            let d = bvh.depth() as usize;
            prop_assert!(d >= ceil_log2(boxes.len()) as usize && d <= boxes.len().saturating_sub(1));
            for q in &queries {
                prop_assert_eq!(bvh.query_aabb(q), brute_aabb(&boxes, q));
            }
            // Every object's own box finds at least itself.
            for (i, b) in boxes.iter().enumerate().take(10) {
                prop_assert!(bvh.query_aabb(b).contains(&(i as u32)));
            }
            for vp in &cams {
                let planes = frustum_planes(vp);
                prop_assert_eq!(bvh.query_frustum(&planes), brute_frustum(&boxes, &planes));
            }
        }
    }

    #[test]
    fn equal_counts_depth_is_ceil_log2(boxes in box_set(300)) {
        let bvh = Bvh::build(&boxes, Split::Eq);
        prop_assert_eq!(bvh.depth(), ceil_log2(boxes.len()));
    }

    /// Arbitrary finite coordinates: huge, subnormal, ±0, f32::MAX.
    #[test]
    fn fuzz_finite_coordinates(
        boxes in prop::collection::vec(any_box(), 0..120),
        q in any_box(),
        vp in view_proj(),
    ) {
        let planes = frustum_planes(&vp);
        for bvh in build_all(&boxes) {
            prop_assert_eq!(bvh.query_aabb(&q), brute_aabb(&boxes, &q));
            prop_assert_eq!(bvh.query_frustum(&planes), brute_frustum(&boxes, &planes));
            let c = bvh.sah_cost();
            prop_assert!(c >= 0.0 && !c.is_nan());
        }
    }

    /// Non-finite and inverted boxes: the builder must terminate without
    /// panicking and place every object in one leaf; validate() accepts
    /// infinities and rejects NaN.
    #[test]
    fn fuzz_non_finite_never_panics(
        raw in prop::collection::vec((prop::array::uniform3(any::<f32>()), prop::array::uniform3(any::<f32>())), 0..80),
    ) {
        let boxes: Vec<Aabb> = raw.iter().map(|&(a, b)| aabb(a, b)).collect();
        let has_nan = raw.iter().any(|(a, b)| a.iter().chain(b).any(|c| c.is_nan()));
        for split in Split::ALL {
            let bvh = Bvh::build(&boxes, split);
            prop_assert_eq!(bvh.nodes.len(), if boxes.is_empty() { 0 } else { 2 * boxes.len() - 1 });
            let mut seen = vec![false; boxes.len()];
            for n in 0..bvh.nodes.len() as u32 {
                if let Some(o) = bvh.object(n) {
                    prop_assert!(!seen[o as usize]);
                    seen[o as usize] = true;
                    prop_assert_eq!(bvh.leaf_of_object[o as usize], n);
                }
            }
            prop_assert!(seen.iter().all(|&s| s));
            prop_assert_eq!(bvh.validate(&boxes).is_ok(), !has_nan, "{}: {:?}", split, bvh.validate(&boxes));
        }
    }
}

// ---------------------------------------------------------------- degenerate inputs

#[test]
fn empty_input_has_no_nodes() {
    for bvh in build_all(&[]) {
        assert!(bvh.nodes.is_empty() && bvh.leaf_of_object.is_empty());
        assert_eq!(bvh.depth(), 0);
        assert_eq!(bvh.sah_cost(), 0.0);
        assert!(bvh.query_aabb(&aabb([-1e30; 3], [1e30; 3])).is_empty());
        assert!(bvh.query_frustum(&frustum_planes(&Mat4::IDENTITY)).is_empty());
    }
}

#[test]
fn single_object_root_is_leaf() {
    let b = [aabb([1.0, 2.0, 3.0], [4.0, 5.0, 6.0])];
    for bvh in build_all(&b) {
        assert_eq!(bvh.nodes.len(), 1);
        assert_eq!(bvh.object(0), Some(0));
        assert_eq!(bvh.children(0), None);
        assert_eq!(bvh.parent(0), None);
        assert_eq!(bvh.leaf_of_object, vec![0]);
        assert_eq!(bvh.aabb(0), b[0]);
        assert_eq!(bvh.depth(), 0);
        assert_eq!(bvh.sah_cost(), 1.0);
        // Closed intervals: touching at a corner overlaps.
        assert_eq!(bvh.query_aabb(&aabb([0.0; 3], [1.0, 2.0, 3.0])), vec![0]);
        assert!(bvh.query_aabb(&aabb([0.0; 3], [1.0, 2.0, 2.9])).is_empty());
    }
}

#[test]
fn two_objects() {
    let b = [aabb([0.0; 3], [1.0; 3]), aabb([5.0; 3], [6.0; 3])];
    for bvh in build_all(&b) {
        assert_eq!(bvh.children(0), Some([1, 2]));
        assert_eq!(bvh.aabb(0), aabb([0.0; 3], [6.0; 3]));
        assert_eq!(bvh.depth(), 1);
    }
}

#[test]
fn identical_boxes() {
    for n in [2, 3, 33, 1000, 5000] {
        let b = vec![aabb([1.0, -2.0, 3.0], [2.0, 0.0, 3.5]); n];
        for bvh in build_all(&b) {
            assert_eq!(bvh.depth(), ceil_log2(n), "coincident centroids split by counts");
            assert_eq!(bvh.query_aabb(&aabb([0.0; 3], [1.0, -2.0, 3.0])).len(), n);
        }
    }
}

#[test]
fn zero_volume_boxes() {
    // Points on a line, points in a plane, flat boxes, and points at one spot.
    let line: Vec<Aabb> = (0..500).map(|i| aabb([i as f32, 0.0, 0.0], [i as f32, 0.0, 0.0])).collect();
    let plane: Vec<Aabb> = (0..900).map(|i| aabb([(i % 30) as f32, 7.0, (i / 30) as f32], [(i % 30) as f32 + 0.5, 7.0, (i / 30) as f32 + 0.5])).collect();
    let spot = vec![aabb([3.0; 3], [3.0; 3]); 100];
    for boxes in [line, plane, spot] {
        for bvh in build_all(&boxes) {
            assert!(bvh.sah_cost().is_finite());
            assert_eq!(bvh.query_aabb(&aabb([-1.0; 3], [1e9; 3])).len(), boxes.len());
        }
    }
    // A root without area has SAH cost 0 by definition.
    assert_eq!(Bvh::build(&vec![aabb([3.0; 3], [3.0; 3]); 10], Split::Sah).sah_cost(), 0.0);
}

#[test]
fn huge_and_mixed_coordinates() {
    let mut boxes = vec![
        aabb([-1e30; 3], [-1e30 + 1e24; 3]),
        aabb([1e30; 3], [1e30; 3]),
        aabb([-1e30, 0.0, 1e30], [1e30, 1.0, 1e30]),
        aabb([f32::MIN; 3], [f32::MAX; 3]),
        aabb([f32::MAX; 3], [f32::MAX; 3]),
    ];
    boxes.extend(random_boxes(300, 7, 0));
    boxes.extend((0..50).map(|i| aabb([i as f32 * 1e-6; 3], [i as f32 * 1e-6 + 1e-7; 3])));
    for bvh in build_all(&boxes) {
        assert_eq!(bvh.aabb(0), aabb([f32::MIN; 3], [f32::MAX; 3]));
        assert!(bvh.sah_cost().is_finite());
        let q = aabb([0.0; 3], [1e-6; 3]);
        assert_eq!(bvh.query_aabb(&q), brute_aabb(&boxes, &q));
    }
    // The SAH still separates a huge-coordinate scene sensibly (f32 areas
    // would overflow at 1e30 and force count splits).
    let far: Vec<Aabb> = random_boxes(2000, 3, 8).iter().map(|b| Aabb::new(b.min * 1e27, b.max * 1e27)).collect();
    let near = random_boxes(2000, 3, 8);
    let (cf, cn) = (Bvh::build(&far, Split::Sah).sah_cost(), Bvh::build(&near, Split::Sah).sah_cost());
    assert!((cf - cn).abs() < 0.05 * cn, "scaled scene cost {cf} vs {cn}");
}

#[test]
fn nan_box_terminates_and_is_rejected() {
    let mut boxes = random_boxes(200, 1, 0);
    boxes[17] = aabb([f32::NAN, 0.0, 0.0], [1.0, f32::NAN, 1.0]);
    boxes[90] = aabb([f32::NAN; 3], [f32::NAN; 3]);
    for split in Split::ALL {
        let bvh = Bvh::build(&boxes, split);
        assert_eq!(bvh.nodes.len(), 399);
        assert!(bvh.validate(&boxes).is_err(), "{split}");
    }
}

#[test]
fn adversarial_exponential_spacing_keeps_depth_bounded() {
    // Points at ±2^k: MID (and SAH) would peel off one object per level.
    let boxes: Vec<Aabb> = (-126..=127).flat_map(|k| [1.0f32, -1.0].map(|s| s * 2f32.powi(k))).map(|x| aabb([x, 0.0, 0.0], [x, 1.0, 1.0])).collect();
    for bvh in build_all(&boxes) {
        assert!(bvh.depth() < 128, "depth {}", bvh.depth());
    }
}

// ---------------------------------------------------------------- quality

#[test]
fn sah_beats_mid_and_eq_on_clustered_data() {
    for seed in 1..=4 {
        let boxes = random_boxes(5000, seed, 12);
        let [sah, mid, eq] = Split::ALL.map(|s| Bvh::build(&boxes, s).sah_cost());
        assert!(sah <= mid && sah <= eq, "seed {seed}: sah {sah} mid {mid} eq {eq}");
    }
}

#[test]
fn sah_cost_definition() {
    // Root [0,2]^3 (area 24), leaves [0,1]^3 and [1,2]^3 (area 6 each).
    let b = [aabb([0.0; 3], [1.0; 3]), aabb([1.0; 3], [2.0; 3])];
    let bvh = Bvh::build(&b, Split::Sah);
    assert!((bvh.sah_cost() - 1.5).abs() < 1e-12);
}

// ---------------------------------------------------------------- validate catches corruption

#[test]
fn validate_rejects_corruption() {
    let boxes = random_boxes(64, 5, 0);
    let good = Bvh::build(&boxes, Split::Sah);
    good.validate(&boxes).unwrap();
    type Corrupt = fn(&mut Bvh);
    let cases: [(&str, Corrupt); 8] = [
        ("parent link", |b| b.nodes[5].parent = 0),
        ("root parent", |b| b.nodes[0].parent = 3),
        ("shrunk box", |b| b.nodes[0].max[1] -= 1.0),
        ("leaf box", |b| {
            let l = b.leaf_of_object[3] as usize;
            b.nodes[l].min[0] -= 1.0
        }),
        ("duplicate object", |b| {
            let (l0, l1) = (b.leaf_of_object[0] as usize, b.leaf_of_object[1] as usize);
            b.nodes[l1].child = b.nodes[l0].child
        }),
        ("leaf_of_object", |b| b.leaf_of_object.swap(0, 1)),
        ("node count", |b| {
            b.nodes.pop();
        }),
        ("cycle", |b| {
            // Point an interior node's pair back at the root's pair.
            let i = (1..b.nodes.len()).find(|&i| b.nodes[i].child & LEAF_BIT == 0).unwrap();
            b.nodes[i].child = 1
        }),
    ];
    for (name, corrupt) in cases {
        let mut bad = good.clone();
        corrupt(&mut bad);
        assert!(bad.validate(&boxes).is_err(), "{name} not detected");
    }
    // Wrong object count.
    assert!(good.validate(&boxes[1..]).is_err());
}

// ---------------------------------------------------------------- API details

#[test]
fn node_layout_is_gpu_ready() {
    assert_eq!(std::mem::size_of::<BvhNode>(), 32);
    let bvh = Bvh::build(&random_boxes(10, 2, 0), Split::Sah);
    let bytes: &[u8] = bytemuck::cast_slice(&bvh.nodes);
    assert_eq!(bytes.len(), 32 * 19);
    // child at byte 12, parent at byte 28 (vec3 + u32, vec3 + u32).
    let root_child = u32::from_le_bytes(bytes[12..16].try_into().unwrap());
    let root_parent = u32::from_le_bytes(bytes[28..32].try_into().unwrap());
    assert_eq!((root_child, root_parent), (1, NO_PARENT));
}

#[test]
fn split_names_round_trip() {
    for s in Split::ALL {
        assert_eq!(s.to_string().parse::<Split>(), Ok(s));
    }
    assert_eq!("SAH".parse::<Split>(), Ok(Split::Sah));
    assert!("median".parse::<Split>().is_err());
    assert_eq!(Split::default(), Split::Sah);
    assert_eq!("eq".parse::<Split>(), Ok(Split::Eq));
}

#[test]
fn large_build_is_parallel_safe_and_deterministic() {
    let boxes = random_boxes(50_000, 11, 20);
    for split in Split::ALL {
        let a = Bvh::build(&boxes, split);
        let b = Bvh::build(&boxes, split);
        a.validate(&boxes).unwrap();
        assert_eq!(a.nodes, b.nodes, "{split}: same input, same tree");
        assert!(a.build_ms > 0.0);
    }
}
