//! The culler's objects after creation: their boxes (from the CPU or a GPU
//! buffer), oriented boxes, slots (added, removed) and flags.

use super::*;

impl Culler {
    /// Moves objects: `(object, new world box)` pairs, taking effect from
    /// the next frame of every view. Static objects are refit into the BVH
    /// ([`MotionOptions::refit`]), which is rebuilt when the policy says
    /// so; [`ObjectFlags::DYNAMIC`] objects only change their own box.
    /// A moved object's [`OrientedBox`] is dropped: give the new one with
    /// [`Culler::set_oriented`].
    /// Errors on an object that is not live or a box that is not finite;
    /// nothing changes then. Views of methods that cannot follow motion
    /// ([`Method::takes_motion`]) refuse their next frame.
    pub fn set_bounds(&mut self, moves: &[(u32, Aabb)]) -> Result<()> {
        for &(i, b) in moves {
            self.check_live(i)?;
            check_box(i, &b)?;
        }
        if moves.is_empty() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        let mut dropped = Vec::new();
        for &(i, b) in moves {
            self.boxes[i as usize] = b;
            if self.oriented[i as usize].take().is_some() {
                dropped.push(i);
            }
        }
        self.upload_oriented(dropped);
        self.moves += 1;
        // Only objects outside the tree moved (HROC §6's hybrid): their
        // boxes are all that changes, with no refit and no policy check.
        if moves.iter().all(|&(i, _)| self.is_dynamic(i as usize) || self.bvh_leaf(i as usize).is_none()) {
            self.upload_bounds();
            self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, ..self.last_update };
            return Ok(());
        }
        self.changed(t)
    }

    /// Moves every object at once from a buffer the host fills on the GPU
    /// (from its own transforms): two `vec4<f32>` per slot, `(min.xyz, _)`
    /// then `(max.xyz, _)`, `32 * capacity` bytes at least, usage `STORAGE`.
    /// Removed slots are ignored. A box that is not finite and ordered is
    /// taken as one around everything (the object is then never culled).
    /// Records the copy and a GPU refit of the static objects into
    /// `encoder`, which the host submits after filling `boxes` and before
    /// the next frame. The CPU's copy of the boxes goes stale: a later
    /// rebuild, or [`Culler::set_bounds`], first reads the GPU's back.
    /// Every [`OrientedBox`] is dropped, as any object may have moved.
    pub fn set_bounds_gpu(&mut self, encoder: &mut wgpu::CommandEncoder, boxes: &wgpu::Buffer) -> Result<()> {
        let need = self.objects.count as u64 * 32;
        if boxes.size() < need || !boxes.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(Error::InvalidObject(format!("bounds buffer of {} bytes, usage {:?}: needs {need} bytes and STORAGE", boxes.size(), boxes.usage())));
        }
        let t = std::time::Instant::now();
        if self.oriented.iter().any(Option::is_some) {
            self.oriented.iter_mut().for_each(|o| *o = None);
            self.upload_oriented(0..self.objects.count);
        }
        self.refit_on_gpu(encoder, Some(boxes));
        self.gpu_boxes = true;
        self.moves += 1;
        self.last_update = UpdateStats { cpu_ms: t.elapsed().as_secs_f64() * 1e3, rebuilt: false, sah_growth: None };
        Ok(())
    }

    /// Adds objects, taking effect from the next frame of every view, and
    /// returns their indices (free slots, lowest first, then new ones). An
    /// object that reuses the slot of a removed one enters the BVH by a
    /// refit; others are tested on their own until the next rebuild.
    /// `first_instance` of each object's command is its index. Errors on a
    /// box that is not finite, and on indices past
    /// [`CullerDesc::index_count`]; nothing changes then.
    pub fn add_objects(&mut self, objects: &[ObjectDesc]) -> Result<Vec<u32>> {
        for (k, o) in objects.iter().enumerate() {
            check_box(k as u32, &o.bounds)?;
            check_indices(k as u32, o, self.index_count)?;
            check_oriented(k as u32, &o.oriented)?;
            check_flags(k as u32, o.flags)?;
        }
        if objects.is_empty() {
            return Ok(Vec::new());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        let live = self.live.iter().filter(|&&l| l).count() as u64;
        if live + objects.len() as u64 > self.objects.count as u64 {
            self.grow((live + objects.len() as u64).next_power_of_two())?;
        }
        let mut ids = Vec::with_capacity(objects.len());
        for o in objects {
            let i = self.free.pop_first().expect("grown to fit");
            let s = i as usize;
            (self.boxes[s], self.oriented[s], self.live[s], self.objects.flags[s]) = (o.bounds, o.oriented, true, o.flags);
            self.objects.cpu_commands[s] = command(o, i);
            ids.push(i);
        }
        self.upload_oriented(ids.iter().copied());
        self.upload_commands();
        self.moves += 1;
        self.update_always();
        self.changed(t)?;
        Ok(ids)
    }

    /// Removes objects, taking effect from the next frame of every view:
    /// their commands draw nothing and their slots are free for
    /// [`Culler::add_objects`]. Errors on an object that is not live, or
    /// listed twice; nothing changes then.
    pub fn remove_objects(&mut self, objects: &[u32]) -> Result<()> {
        let mut seen = std::collections::HashSet::new();
        for &i in objects {
            self.check_live(i)?;
            if !seen.insert(i) {
                return Err(Error::InvalidObject(format!("object {i} listed twice")));
            }
        }
        if objects.is_empty() {
            return Ok(());
        }
        let t = std::time::Instant::now();
        self.sync_boxes()?;
        for &i in objects {
            let s = i as usize;
            (self.live[s], self.objects.flags[s], self.oriented[s]) = (false, ObjectFlags::NONE, None);
            self.objects.cpu_commands[s] = DrawCommand::default();
            self.free.insert(i);
        }
        self.upload_oriented(objects.iter().copied());
        self.upload_commands();
        self.moves += 1;
        self.update_always();
        self.changed(t)
    }

    /// Gives objects an [`OrientedBox`] (`Some`) or takes it away (`None`),
    /// from the next frame of every view; their world boxes stay as they
    /// are. Errors on an object that is not live, or a box that is not
    /// finite and invertible; nothing changes then.
    pub fn set_oriented(&mut self, boxes: &[(u32, Option<OrientedBox>)]) -> Result<()> {
        for (i, b) in boxes {
            self.check_live(*i)?;
            check_oriented(*i, b)?;
        }
        for &(i, b) in boxes {
            self.oriented[i as usize] = b;
        }
        self.upload_oriented(boxes.iter().map(|b| b.0));
        Ok(())
    }

    /// The object's [`OrientedBox`], if it has one.
    pub fn oriented(&self, i: u32) -> Option<OrientedBox> {
        self.oriented.get(i as usize).copied().flatten()
    }

    /// The flags of object `i`; `None` when it is not live.
    pub fn flags(&self, i: u32) -> Option<ObjectFlags> {
        self.is_live(i).then(|| self.objects.flags[i as usize])
    }

    pub(super) fn check_live(&self, i: u32) -> Result<()> {
        match self.is_live(i) {
            true => Ok(()),
            false if i < self.objects.count => Err(Error::InvalidObject(format!("object {i} was removed (or never added)"))),
            false => Err(Error::InvalidObject(format!("object {i} out of range 0..{}", self.objects.count))),
        }
    }

    /// Sets the flags of object `i` (an object that turns transparent, a
    /// door that starts to move): takes effect from the next frame of every
    /// view. An object turned [`ObjectFlags::DYNAMIC`] leaves the tree's
    /// boxes as they were; one turned static again is refit into its leaf,
    /// or tested on its own until the next rebuild when it has none.
    pub fn set_flags(&mut self, i: u32, flags: ObjectFlags) -> Result<()> {
        self.set_many_flags(&[(i, flags)])
    }

    /// [`Culler::set_flags`] for many objects at once: one refit and one
    /// upload for all of them. Errors on an object that is not live or an
    /// unknown flag; nothing changes then.
    pub fn set_many_flags(&mut self, changes: &[(u32, ObjectFlags)]) -> Result<()> {
        for &(i, f) in changes {
            self.check_live(i)?;
            check_flags(i, f)?;
        }
        let mut motion = false;
        for &(i, f) in changes {
            let was = std::mem::replace(&mut self.objects.flags[i as usize], f);
            motion |= was.contains(ObjectFlags::DYNAMIC) != f.contains(ObjectFlags::DYNAMIC);
        }
        self.update_always();
        if motion {
            let t = std::time::Instant::now();
            self.sync_boxes()?;
            self.moves += 1;
            return self.changed(t);
        }
        for &(i, _) in changes {
            self.gpu.queue.write_buffer(&self.objects.bounds, i as u64 * 32 + 12, bytemuck::bytes_of(&self.gpu_flags(i as usize)));
        }
        Ok(())
    }

    /// Rebuilds the never-culled list and the never-culled non-occluders.
    pub(super) fn update_always(&mut self) {
        let o = &mut self.objects;
        let never = |f: &ObjectFlags| f.contains(ObjectFlags::NEVER_CULL);
        let list: Vec<DrawCommand> = o.flags.iter().zip(&o.cpu_commands).filter(|(f, _)| never(f) && !f.contains(ObjectFlags::NOT_OCCLUDER)).map(|(_, c)| *c).collect();
        let deferred: Vec<u32> = o.flags.iter().map(|f| (never(f) && f.contains(ObjectFlags::NOT_OCCLUDER)) as u32).collect();
        if !deferred.is_empty() {
            self.gpu.queue.write_buffer(&o.always_deferred, 0, bytemuck::cast_slice(&deferred));
        }
        o.always = (!list.is_empty()).then(|| {
            use wgpu::BufferUsages as U;
            DrawList {
                commands: self.gpu.buffer_init("hroc never-culled", bytemuck::cast_slice(&list), U::STORAGE | U::INDIRECT | U::COPY_SRC),
                count: self.gpu.buffer_init("hroc never-culled count", bytemuck::bytes_of(&(list.len() as u32)), U::STORAGE | U::INDIRECT | U::COPY_SRC),
                max_count: list.len() as u32,
            }
        });
    }
}
