// With hroc's early-Z marks, for a cascade culled by a method that reads
// them: the fragment stage forces early-Z and marks its object (hroc_mark,
// from hroc::device::marks_wgsl(1) appended below).

@fragment @early_depth_test(force)
fn fs_shadow_marked(in: ShadowOut) {
    hroc_mark(in.object);
}
