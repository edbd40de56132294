//! HROC's per-view state: its buffers, pipelines and bind groups, built
//! once for the view's targets.

use super::*;
use crate::gpu::shape::DeviceShape;
use crate::shaders::BoxTarget;

impl Hroc {
    /// Creates the method's buffers and pipelines; fails if the BVH is deeper than [`MAX_DEPTH`].
    pub fn new(variant: Variant, cx: &MethodContext) -> Result<Self> {
        let (gpu, bvh) = (cx.gpu, cx.bvh);
        if bvh.depth() > MAX_DEPTH {
            return Err(Error::InvalidScene(format!("BVH depth {} exceeds {MAX_DEPTH}, which HROC's traversal stacks hold; try --split eq", bvh.depth())));
        }
        let n = cx.object_count;
        let scale = test_scale(cx.options.hroc_test_scale, cx.targets.size);
        let filter_stride = cx.options.hroc_filter_stride.max(1);
        let samples = cx.targets.samples;
        // Rebuilds keep the buffers: size them for the largest tree.
        let nodes = cx.node_capacity;
        use wgpu::BufferUsages as U;
        let flags = |label| gpu.buffer(label, n as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let (visible, occluders, occludees, drawn) = (flags("hroc V"), flags("hroc O"), flags("hroc U"), flags("hroc D"));
        let state = gpu.buffer("hroc node state", nodes as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let visited = gpu.buffer("hroc visited", nodes as u64 * 4, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        let group_count = gpu.buffer("hroc |G|", 4, U::STORAGE | U::INDIRECT | U::COPY_DST | U::COPY_SRC);
        // Step 2's counts and candidates, and the collection's workgroups
        // (hroc_groups.wgsl); step 5 resets both for the next frame.
        let walk = gpu.buffer("hroc walk", (4 + nodes as u64) * 4, U::STORAGE | U::COPY_SRC | U::COPY_DST);
        let collect_launch = gpu.buffer_init("hroc collect workgroups", bytemuck::cast_slice(&COLLECT_LAUNCH), U::STORAGE | U::INDIRECT | U::COPY_DST);
        let collect_init = gpu.buffer_init("hroc collect workgroups at rest", bytemuck::cast_slice(&COLLECT_LAUNCH), U::COPY_SRC);
        let ray_stats = gpu.buffer("hroc ray stats", STAT_SLOTS * 8, U::STORAGE | U::COPY_DST | U::COPY_SRC);
        // A group per node, or per object tested alone (§6's hybrid).
        let groups = gpu.buffer("hroc groups", (nodes as u64 + n as u64) * 16, U::STORAGE | U::INDIRECT | U::COPY_SRC);
        let compactor = Compactor::new(gpu, n);
        let (v_list, v_job) = compactor.packed_list(gpu, "hroc V list", &visible, cx.commands);
        let (u_list, u_job) = compactor.packed_list(gpu, "hroc U list", &occludees, cx.commands);
        let nodes_buf = cx.bvh_nodes.clone();
        let leaf_of_object = cx.leaf_of_object.clone();

        let device = &gpu.device;
        // Without OF no pass reads the ID target; a 1x1 stand-in fills the binding.
        let stand_in;
        let ids = match cx.targets.ids.as_ref() {
            Some(v) => v,
            None => {
                stand_in = gpu.stand_in("hroc no ids", wgpu::TextureFormat::Rg16Uint, cx.targets.samples);
                &stand_in
            }
        };
        // Steps 0, 2 and 5 number their bindings alike (hroc_groups.wgsl).
        let bufs = [cx.frame, &nodes_buf, &leaf_of_object, &occluders, &state, &groups, &group_count, &occludees, &drawn, &visible];
        let mut resources: Vec<(u32, wgpu::BindingResource)> = bufs.iter().enumerate().map(|(i, b)| (i as u32, b.as_entire_binding())).collect();
        let grid = seed_grid(cx.targets.size);
        let cells = grid.0 * grid.1;
        let covered = gpu.buffer("hroc covered cells", cells as u64 * 4, U::STORAGE | U::COPY_DST);
        let refill_list = DrawList {
            commands: gpu.buffer("hroc refill list", cells as u64 * std::mem::size_of::<crate::layout::DrawCommand>() as u64, U::STORAGE | U::INDIRECT | U::COPY_DST | U::COPY_SRC),
            count: gpu.buffer("hroc refill count", 4, U::STORAGE | U::INDIRECT | U::COPY_DST | U::COPY_SRC),
            max_count: cells,
        };
        resources.extend([
            (10, wgpu::BindingResource::TextureView(ids)),
            (11, cx.bounds.as_entire_binding()),
            (12, wgpu::BindingResource::TextureView(&cx.targets.depth_sampled)),
            (13, cx.commands.as_entire_binding()),
            (14, refill_list.commands.as_entire_binding()),
            (15, refill_list.count.as_entire_binding()),
            (16, covered.as_entire_binding()),
            (17, occluders.as_entire_binding()),
            (18, collect_launch.as_entire_binding()),
            (19, walk.as_entire_binding()),
        ]);
        // OF only where it changes the next V: where D is marked, which the
        // merge needs (early-Z marks; OF with ID or box marks leaves D
        // unmarked), and without rounds.
        let marks_d = cx.mark_target(&drawn, None);
        let no_rounds = cx.options.hroc_rounds <= 1 && !cx.options.hroc_occluder_rounds;
        let filter_gated = matches!(marks_d, MarkTarget::Host(..));
        let gated = no_rounds && ((variant.of && filter_gated) || cx.options.hroc_frustum_below > 0.0);
        let pixels = cx.targets.size.0 as f64 * cx.targets.size.1 as f64;
        let pays = Pays { share: cx.options.hroc_frustum_below, triangles: cx.options.hroc_frustum_triangles as f64 * pixels };
        let gate = gated.then(|| Gate::new(gpu, variant.of, filter_gated, pays));
        let gate_tally = match &gate {
            Some(g) => g.tally.clone(),
            None => gpu.buffer("hroc gate tally", gate::TALLY, U::STORAGE),
        };
        resources.push((20, gate_tally.as_entire_binding()));
        let step = |layout: Layout, pass: &str, entry: &str, constants: &[(&str, f64)]| {
            let bind_layout = layout.create_for(gpu, samples);
            let module = gpu.shader(pass, &shader_source_for(pass, samples));
            let pipeline = gpu.compute_pipeline(&module, entry, Some(&crate::reflect::pipeline_layout(gpu, layout.label(), &bind_layout)), constants);
            Step { pipeline, bind: layout.bind(gpu, &bind_layout, &resources) }
        };
        let test_scale = [("TEST_SCALE", scale as f64)];
        let grid_size = grid;
        let grid = [("SEED_COLS", grid.0 as f64), ("SEED_ROWS", grid.1 as f64)];
        let seed = step(Layout::HrocSeed, "hroc_seed.wgsl", "seed", &grid);
        let refill = step(Layout::HrocSeed, "hroc_seed.wgsl", "refill_holes", &grid);
        let extract = step(Layout::HrocWalk, "hroc_groups.wgsl", "extract", &[]);
        let alone = step(Layout::HrocGroups, "hroc_groups.wgsl", "alone", &test_scale);
        let collect = step(Layout::HrocGroups, "hroc_groups.wgsl", "collect", &test_scale);
        // Step 5 records the covered cells where the refill reads them.
        let cover = [("COVER", (cx.options.hroc_seed == Seed::Cuts) as u32 as f64), grid[0], grid[1]];
        // Marks from boxes, in one pass at the end of the frame (`Hroc::marks_at_end`).
        let marks_at_end = cx.capabilities.marks == crate::capabilities::Marks::Boxes && !variant.of && cx.options.hroc_rounds <= 1 && !cx.options.hroc_occluder_rounds;
        let merge = step(Layout::HrocNext, "hroc_next.wgsl", "merge", &[cover[0], cover[1], cover[2], ("OCCLUDERS_STAY", (!marks_at_end) as u32 as f64)]);
        let filter_step = |measure: bool| {
            step(
                Layout::HrocNext,
                "hroc_next.wgsl",
                "filter_occluders",
                &[cover[0], cover[1], cover[2], ("FILTER_STRIDE", filter_stride as f64), ("FILTER_TILE", FILTER_TILE as f64), ("MEASURE", measure as u32 as f64)],
            )
        };
        let (filter, probe) = (filter_step(false), (gate.is_some() && variant.of && filter_gated).then(|| filter_step(true)));
        // What occlusion culls is counted, and frustum frames run, only where
        // a share of it is asked for (not in `auto`'s HROC).
        let (measure, frustum) = match gate.is_some() && cx.options.hroc_frustum_below > 0.0 {
            true => (Some(step(Layout::HrocYield, "hroc_yield.wgsl", "measure", &[])), Some(step(Layout::HrocYield, "hroc_yield.wgsl", "frustum", &[]))),
            false => (None, None),
        };

        let test_layout = Layout::HrocTest.create_for(gpu, samples);
        let test_module = gpu.shader("hroc_test.wgsl", &shader_source_for("hroc_test.wgsl", samples));
        // Multisampled depth is reduced to blocks (of one pixel at least):
        // the boxes are tested against the blocks' map, and the rays take
        // each block's farthest sample from the host's depth, which they load.
        let blocks = (scale > 1 || samples > 1).then(|| Blocks::new(gpu, cx, &test_module, scale));
        let occlusion_map = &cx.targets.depth_sampled;
        let test_bind = device.counted_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hroc test"),
            layout: &test_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: cx.frame.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: nodes_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: occludees.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: visited.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(occlusion_map) },
                wgpu::BindGroupEntry { binding: 5, resource: ray_stats.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: cx.bounds.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 15, resource: cx.oriented.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 16, resource: groups.as_entire_binding() },
            ],
        });
        let test_pl = crate::reflect::pipeline_layout(gpu, "hroc test", &test_layout);
        let test_depth = match blocks {
            Some(_) => (BLOCK_FORMAT, cx.targets.depth, 1),
            None => (cx.targets.depth_format, cx.targets.depth, samples),
        };
        // Without early-Z marks, the test binds no depth and compares each
        // fragment itself; so too where its rays sample the depth it would
        // attach (the host's, without blocks) and attachments cannot be
        // read-only.
        let (w, h) = cx.targets.size;
        let test_target = BoxTarget::new(gpu, cx.capabilities, blocks.is_none(), if blocks.is_some() { ((w / scale, h / scale), 1) } else { ((w, h), samples) });
        let constants = [("TEST_SCALE", scale as f64), ("MANUAL_DEPTH", test_target.manual_depth())];
        // With an emulated draw count, the groups are one instanced draw of
        // `group_args` (36 vertices, |G| instances copied in each frame).
        let group_args =
            (cx.capabilities.draw_count == DrawCount::Emulated).then(|| gpu.buffer_init("hroc group draw", bytemuck::cast_slice(&[36u32, 0, 0, 0]), U::INDIRECT | U::COPY_DST));
        let vertex = if group_args.is_some() { "group_vs" } else { "box_vs" };
        let boxes = crate::shaders::box_pipeline(gpu, "hroc boxes", &test_pl, &test_module, (vertex, Some("box_fs")), test_depth, test_target.mode(), &constants);
        let round_count = cx.options.hroc_rounds.clamp(1, MAX_ROUNDS);
        let rounds = (round_count > 1).then(|| Rounds::new(gpu, cx, &test_module, scale, test_depth, occlusion_map, round_count, &occludees, &u_list, &compactor));
        let occluder_rounds =
            cx.options.hroc_occluder_rounds.then(|| Rounds::new(gpu, cx, &test_module, scale, test_depth, occlusion_map, OCCLUDER_ROUNDS, &visible, &v_list, &compactor));
        let words = |bytes: usize| (bytes / 4) as u32;
        let command_words = words(std::mem::size_of::<crate::layout::DrawCommand>());
        // With an emulated draw count every list is drawn to its capacity
        // anyway: an estimate and its overflow would only add passes.
        let sf = (variant.counters == Counters::StallFree && cx.capabilities.draw_count == DrawCount::Indirect).then(|| {
            let last = rounds.as_ref().map_or(&u_list, |r| &r.last.0);
            fn of(l: &DrawList, n: u32, words: u32) -> Option<(&wgpu::Buffer, &wgpu::Buffer, u32, u32)> {
                Some((&l.commands, &l.count, n, words))
            }
            let counted = |l| of(l, n, command_words);
            let mut lists = vec![counted(&v_list), Some((&groups, &group_count, nodes + n, 0)), counted(last)];
            // V's two lists, with occluder rounds only.
            let v_rounds = occluder_rounds.as_ref().map(|r| (&r.fronts[0].0, &r.last.0));
            lists.extend([v_rounds.and_then(|v| counted(v.0)), v_rounds.and_then(|v| counted(v.1))]);
            lists.extend(rounds.iter().flat_map(|r| &r.fronts).map(|(l, _)| counted(l)));
            StallFree::new(gpu, &lists)
        });
        let sf = sf.flatten();
        let spare_v =
            (occluder_rounds.is_none() && sf.as_ref().is_none_or(|sf| sf.estimate(Counted::V).is_none())).then(|| compactor.packed_list(gpu, "hroc V list", &visible, cx.commands));
        Ok(Hroc {
            variant,
            n,
            nodes,
            tree_nodes: bvh.nodes.len() as u32,
            // O skips the test of what it marks: only V's own objects.
            marks_o: cx.mark_target(&occluders, Some(&visible)),
            marks_d,
            marks_at_end,
            extract,
            alone,
            collect,
            walk,
            collect_launch,
            collect_init,
            walk_open: false,
            merge,
            filter,
            probe,
            gate,
            measure,
            frustum,
            plan: Plan::whole(variant.of),
            planned: None,
            filter_stride,
            grid: grid_size,
            seed,
            refill,
            refill_list,
            visible,
            occluders,
            occludees,
            drawn,
            state,
            visited,
            group_count,
            ray_stats,
            v_drawn: v_list.clone(),
            v_list,
            spare_v,
            v_packed: None,
            u_list,
            groups,
            compactor,
            v_job,
            u_job,
            test_bind,
            boxes,
            test_target,
            group_args,
            blocks,
            last: SetSizes::default(),
            seed_mode: cx.options.hroc_seed,
            seed_next: true,
            seeded: false,
            sf,
            rounds,
            occluder_rounds,
        })
    }
}
