//! CPU reference of IOC's level iteration (and the host-side tables the
//! GPU pass uses): the start queue, leaf ranges, and the queues and visible
//! objects that follow from per-node test outcomes.

use crate::bvh::Bvh;

/// Depth of every node (root = 0). Children follow their parent.
pub fn node_depths(bvh: &Bvh) -> Vec<u32> {
    let mut d = vec![0u32; bvh.nodes.len()];
    for n in 0..bvh.nodes.len() as u32 {
        if let Some([l, r]) = bvh.children(n) {
            d[l as usize] = d[n as usize] + 1;
            d[r as usize] = d[n as usize] + 1;
        }
    }
    d
}

/// The first level's queue: every node at depth `start`, plus the leaves
/// shallower than `start` (nodes above `start` are not tested, so without
/// those leaves their objects would never be considered). Together they
/// form a cut of the tree: every leaf has exactly one ancestor-or-self in
/// it. Sorted by node index.
pub fn start_queue(bvh: &Bvh, start: u32) -> Vec<u32> {
    node_depths(bvh).iter().enumerate().filter(|(n, &d)| d == start || (d < start && bvh.is_leaf(*n as u32))).map(|(n, _)| n as u32).collect()
}

/// Objects in depth-first leaf order, and per node the range (first,
/// count) of that order its subtree holds.
pub fn leaf_ranges(bvh: &Bvh) -> (Vec<u32>, Vec<[u32; 2]>) {
    let len = bvh.nodes.len();
    let mut count = vec![0u32; len];
    for n in (0..len as u32).rev() {
        count[n as usize] = match bvh.children(n) {
            Some([l, r]) => count[l as usize] + count[r as usize],
            None => 1,
        };
    }
    let mut first = vec![0u32; len];
    let mut order = vec![0u32; bvh.leaf_of_object.len()];
    for n in 0..len as u32 {
        match bvh.children(n) {
            Some([l, r]) => {
                first[l as usize] = first[n as usize];
                first[r as usize] = first[n as usize] + count[l as usize];
            }
            None => order[first[n as usize] as usize] = bvh.object(n).unwrap_or(0),
        }
    }
    (order, first.into_iter().zip(count).map(|(f, c)| [f, c]).collect())
}

/// What one IOC frame decides, given per-node outcomes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Levels {
    /// The queue of each level tested, from `start` on, each sorted.
    pub queues: Vec<Vec<u32>>,
    /// Per object: below a node that passed at the bottom level, or a leaf that passed.
    pub visible: Vec<bool>,
}

/// IOC's traversal from `start` to `bottom`; `passed(n)` is the outcome of
/// node `n`'s test (a passing fragment, or visible without a test).
pub fn levels(bvh: &Bvh, start: u32, bottom: u32, passed: impl Fn(u32) -> bool) -> Levels {
    let mut out = Levels { queues: Vec::new(), visible: vec![false; bvh.leaf_of_object.len()] };
    if bvh.nodes.is_empty() {
        return out;
    }
    let mut queue = start_queue(bvh, start);
    let mut level = start;
    while !queue.is_empty() {
        queue.sort_unstable();
        let mut next = Vec::new();
        for &n in &queue {
            if !passed(n) {
                continue;
            }
            match bvh.children(n) {
                None => out.visible[bvh.object(n).unwrap_or(0) as usize] = true,
                Some(_) if level >= bottom => {
                    let mut stack = vec![n];
                    while let Some(m) = stack.pop() {
                        match bvh.children(m) {
                            Some([l, r]) => stack.extend([l, r]),
                            None => out.visible[bvh.object(m).unwrap_or(0) as usize] = true,
                        }
                    }
                }
                Some([l, r]) => next.extend([l, r]),
            }
        }
        out.queues.push(std::mem::replace(&mut queue, next));
        if level >= bottom {
            break;
        }
        level += 1;
    }
    out
}

/// The default depth range for a BVH of `depth`: [depth/2 - 1, depth/2 + 1]
/// (the paper's tuned ranges sit around the middle of the tree: [9, 11] for
/// RC at depth 22, [14, 17] for ST at depth 25).
pub fn default_range(depth: u32) -> (u32, u32) {
    ((depth / 2).saturating_sub(1), (depth / 2 + 1).min(depth))
}
