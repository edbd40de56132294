// With hroc's early-Z marks (hroc::device::Marks::EarlyZ): the opaque fragment
// stage forces early-Z and marks its object (hroc_mark, from
// hroc::device::marks_wgsl(1) appended below), so a mark means a fragment passed.

@fragment @early_depth_test(force)
fn fs_opaque_marked(in: VsOut) -> Opaque {
    hroc_mark(in.object);
    return opaque(in);
}
