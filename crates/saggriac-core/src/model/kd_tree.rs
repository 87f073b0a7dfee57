//! Our own exact, incremental k-d tree, for the episodic memory (unordered movements in a few
//! dimensions, where boxes over insertion order do not prune; see `block_index.rs` for the
//! micro-action memory).
//!
//! Why not only the `kdtree` crate: its search allocates a vector at every node it visits and
//! keeps a heap of nodes, which dominated our profiles (see benchmarks/). This tree keeps each
//! leaf's coordinates contiguous, searches depth first without allocating, accepts a starting
//! radius (the warm start), and orders by (distance, id) so it returns exactly what the
//! brute-force reference returns, ties included.

use crate::model::neighbours::{distances, Neighbour, NeighbourIndex, TopK};

const BUCKET: usize = 48;

/// A leaf stores its coordinates dimension-major (all first coordinates, then all second ...,
/// with a stride of `cap`), so the distance kernel runs over points in SIMD lanes.
#[derive(Debug, Clone, Default)]
struct Leaf {
    ids: Vec<u32>,
    cap: usize,
    coords: Vec<f64>,
}

impl Leaf {
    fn push(&mut self, dim: usize, id: u32, p: &[f64]) {
        let len = self.ids.len();
        if len == self.cap {
            let cap = (self.cap * 2).max(BUCKET + 1);
            let mut c = vec![0.0; dim * cap];
            for d in 0..dim {
                c[d * cap..d * cap + len].copy_from_slice(&self.coords[d * self.cap..d * self.cap + len]);
            }
            self.coords = c;
            self.cap = cap;
        }
        for (d, v) in p.iter().enumerate() {
            self.coords[d * self.cap + len] = *v;
        }
        self.ids.push(id);
    }
    fn point(&self, dim: usize, j: usize, out: &mut [f64]) {
        for (d, o) in out.iter_mut().enumerate().take(dim) {
            *o = self.coords[d * self.cap + j];
        }
    }
}

#[derive(Debug, Clone)]
enum Node {
    Leaf(Leaf),
    Inner { dim: usize, value: f64, left: usize, right: usize },
}

#[derive(Debug, Clone)]
pub struct KdTree {
    dim: usize,
    nodes: Vec<Node>,
    /// Tight bounding box of the points under each node: lo at [i*2*dim..], hi after it.
    bounds: Vec<f64>,
    len: usize,
    /// Size at the last rebuild. Cuts chosen while the data was sparse fit the dense data that
    /// comes later badly, so the tree is rebuilt balanced each time its size doubles
    /// (amortised O(log n) per insertion).
    built_at: usize,
}

impl KdTree {
    pub fn new(dim: usize) -> Self {
        let mut t = KdTree { dim, nodes: Vec::new(), bounds: Vec::new(), len: 0, built_at: 0 };
        t.push_node(Node::Leaf(Leaf::default()));
        t
    }

    fn push_node(&mut self, node: Node) -> usize {
        self.nodes.push(node);
        self.bounds.extend(std::iter::repeat_n(f64::INFINITY, self.dim));
        self.bounds.extend(std::iter::repeat_n(f64::NEG_INFINITY, self.dim));
        self.nodes.len() - 1
    }

    #[inline]
    fn extend_bounds(&mut self, node: usize, p: &[f64]) {
        let d = self.dim;
        let b = &mut self.bounds[node * 2 * d..(node + 1) * 2 * d];
        let (lo, hi) = b.split_at_mut(d);
        for i in 0..d {
            if p[i] < lo[i] {
                lo[i] = p[i];
            }
            if p[i] > hi[i] {
                hi[i] = p[i];
            }
        }
    }

    /// Could the bounding box of `node` hold a point within squared distance `limit` of q?
    ///
    /// The box's squared distance is summed in four independent lanes (no chain of dependent
    /// additions), so its rounding differs from a point distance summed dimension by dimension.
    /// Each box term is at most the matching term of any point in the box (both rounded the
    /// same monotone way), and two sums of the same n terms in different orders differ by a
    /// factor of at most (1 + n u) / (1 - n u); the 1e-12 slack covers that for n up to
    /// thousands, so a box is only skipped when every point in it is strictly beyond `limit`.
    #[inline]
    fn box_within(&self, node: usize, q: &[f64], limit: f64) -> bool {
        let d = self.dim;
        let b = &self.bounds[node * 2 * d..(node + 1) * 2 * d];
        let (lo, hi) = b.split_at(d);
        let mut acc = [0.0f64; 4];
        let gap = |i: usize| {
            let v = q[i];
            let e = (lo[i] - v).max(0.0) + (v - hi[i]).max(0.0);
            e * e
        };
        let mut i = 0;
        while i + 4 <= d {
            for (l, a) in acc.iter_mut().enumerate() {
                *a += gap(i + l);
            }
            i += 4;
        }
        for (l, a) in acc.iter_mut().enumerate().take(d - i) {
            *a += gap(i + l);
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3]) <= limit * (1.0 + 1e-12)
    }

    /// Rebuild the whole tree balanced: median cuts on the widest dimension of each node.
    fn rebuild(&mut self) {
        let d = self.dim;
        let mut coords = vec![0.0; self.len * d];
        for node in &self.nodes {
            if let Node::Leaf(leaf) = node {
                for (j, id) in leaf.ids.iter().enumerate() {
                    leaf.point(d, j, &mut coords[*id as usize * d..(*id as usize + 1) * d]);
                }
            }
        }
        self.nodes.clear();
        self.bounds.clear();
        let mut ids: Vec<u32> = (0..self.len as u32).collect();
        self.build(&mut ids, &coords);
        self.built_at = self.len;
    }

    fn build(&mut self, ids: &mut [u32], coords: &[f64]) -> usize {
        let d = self.dim;
        let node = self.push_node(Node::Leaf(Leaf::default()));
        for &id in ids.iter() {
            self.extend_bounds(node, &coords[id as usize * d..(id as usize + 1) * d]);
        }
        let (dim, spread) = {
            let b = &self.bounds[node * 2 * d..(node + 1) * 2 * d];
            (0..d).map(|i| (i, b[d + i] - b[i])).fold((0, 0.0), |a, x| if x.1 > a.1 { x } else { a })
        };
        if ids.len() <= BUCKET || spread <= 0.0 {
            let mut leaf_ids = ids.to_vec();
            leaf_ids.sort_unstable();
            let mut leaf = Leaf::default();
            for id in leaf_ids {
                leaf.push(d, id, &coords[id as usize * d..(id as usize + 1) * d]);
            }
            self.nodes[node] = Node::Leaf(leaf);
            return node;
        }
        let key = |id: &u32| coords[*id as usize * d + dim];
        let mid = ids.len() / 2;
        ids.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
        let mut value = key(&ids[mid]);
        let lo = self.bounds[node * 2 * d + dim];
        if value <= lo {
            value = ids.iter().map(key).filter(|v| *v > lo).fold(f64::INFINITY, f64::min);
        }
        // Partition: strictly below the cut to the left.
        let mut i = 0;
        for j in 0..ids.len() {
            if key(&ids[j]) < value {
                ids.swap(i, j);
                i += 1;
            }
        }
        let (l, r) = ids.split_at_mut(i);
        let left = self.build(l, coords);
        let right = self.build(r, coords);
        self.nodes[node] = Node::Inner { dim, value, left, right };
        node
    }

    fn split_leaf(&mut self, node: usize) {
        let d = self.dim;
        let (dim, spread) = {
            let b = &self.bounds[node * 2 * d..(node + 1) * 2 * d];
            (0..d).map(|i| (i, b[d + i] - b[i])).fold((0, 0.0), |a, x| if x.1 > a.1 { x } else { a })
        };
        if spread <= 0.0 {
            // All points identical: a split cannot separate them; the leaf just grows.
            return;
        }
        let leaf = match std::mem::replace(&mut self.nodes[node], Node::Leaf(Leaf::default())) {
            Node::Leaf(leaf) => leaf,
            Node::Inner { .. } => unreachable!("split_leaf on an inner node"),
        };
        let n = leaf.ids.len();
        // Median of the split coordinate: balanced children whatever the data's shape.
        let mut vals: Vec<f64> = leaf.coords[dim * leaf.cap..dim * leaf.cap + n].to_vec();
        let mid = vals.len() / 2;
        let (_, m, _) = vals.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
        let mut value = *m;
        let lo = self.bounds[node * 2 * d + dim];
        if value <= lo {
            // Many points at the minimum: put the cut just above them.
            value = vals.iter().cloned().filter(|v| *v > lo).fold(f64::INFINITY, f64::min);
        }
        let left = self.push_node(Node::Leaf(Leaf::default()));
        let right = self.push_node(Node::Leaf(Leaf::default()));
        let mut p = vec![0.0; d];
        for (j, id) in leaf.ids.iter().enumerate() {
            leaf.point(d, j, &mut p);
            let child = if p[dim] < value { left } else { right };
            self.extend_bounds(child, &p);
            if let Node::Leaf(l) = &mut self.nodes[child] {
                l.push(d, *id, &p);
            }
        }
        self.nodes[node] = Node::Inner { dim, value, left, right };
    }

    fn search(&self, node: usize, q: &[f64], best: &mut TopK<'_>, acc: &mut Vec<f64>) {
        match &self.nodes[node] {
            Node::Leaf(leaf) => {
                let len = leaf.ids.len();
                if acc.len() < len {
                    acc.resize(len, 0.0);
                }
                distances(q, &leaf.coords, leaf.cap, len, acc);
                let mut bound = best.bound();
                for (j, &dsq) in acc.iter().enumerate().take(len) {
                    if dsq <= bound {
                        best.offer(leaf.ids[j], dsq);
                        bound = best.bound();
                    }
                }
            }
            Node::Inner { dim, value, left, right } => {
                let (near, far) = if q[*dim] < *value { (*left, *right) } else { (*right, *left) };
                if self.box_within(near, q, best.bound()) {
                    self.search(near, q, best, acc);
                }
                // The far side lies beyond the cut plane: a one-coordinate test first, the tight
                // box only if the plane is close enough.
                let plane = q[*dim] - *value;
                if plane * plane <= best.bound() && self.box_within(far, q, best.bound()) {
                    self.search(far, q, best, acc);
                }
            }
        }
    }
}

impl NeighbourIndex for KdTree {
    fn dim(&self) -> usize {
        self.dim
    }
    fn len(&self) -> usize {
        self.len
    }
    fn add(&mut self, point: &[f64]) {
        debug_assert_eq!(point.len(), self.dim);
        let id = self.len as u32;
        self.len += 1;
        let mut node = 0;
        loop {
            self.extend_bounds(node, point);
            match &mut self.nodes[node] {
                Node::Inner { dim, value, left, right } => {
                    node = if point[*dim] < *value { *left } else { *right };
                }
                Node::Leaf(leaf) => {
                    leaf.push(self.dim, id, point);
                    let n = leaf.ids.len();
                    if n > BUCKET && n % BUCKET == 1 {
                        self.split_leaf(node);
                    }
                    if self.len >= 1024 && self.len >= 2 * self.built_at {
                        self.rebuild();
                    }
                    return;
                }
            }
        }
    }
    fn knn_within(&self, query: &[f64], k: usize, radius_sq: f64, out: &mut Vec<Neighbour>) {
        out.clear();
        if k == 0 || self.len == 0 {
            return;
        }
        let mut best = TopK::new(out, k, radius_sq);
        let mut acc = vec![0.0; 2 * BUCKET];
        if self.box_within(0, query, radius_sq) {
            self.search(0, query, &mut best, &mut acc);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::neighbours::reference::assert_matches_brute;
    use crate::rng::{rng_from_seed, uniform};

    fn compare(points: &[f64], dim: usize, queries: &[f64], k: usize) {
        assert_matches_brute(&mut KdTree::new(dim), points, queries, k);
    }

    #[test]
    fn matches_brute_force_on_random_data() {
        let mut r = rng_from_seed(11);
        for &dim in &[1usize, 2, 15] {
            let pts: Vec<f64> = (0..2000 * dim).map(|_| uniform(&mut r, -1.0, 1.0)).collect();
            let qs: Vec<f64> = (0..40 * dim).map(|_| uniform(&mut r, -1.2, 1.2)).collect();
            for &k in &[1usize, 7, 45, 3000] {
                compare(&pts, dim, &qs, k);
            }
        }
    }

    #[test]
    fn matches_brute_force_with_duplicates_and_ties() {
        // Rest poses repeated many times, a grid (equal distances everywhere) and a trajectory.
        let dim = 15;
        let mut pts = vec![0.0; 700 * dim];
        for i in 0..400 {
            let mut p = vec![0.0; dim];
            p[i % dim] = ((i / dim) % 3) as f64 * 0.5;
            pts.extend(p);
        }
        let mut r = rng_from_seed(2);
        let mut t = vec![0.0; dim];
        for _ in 0..1500 {
            t.iter_mut().for_each(|v| *v += uniform(&mut r, -0.01, 0.01));
            pts.extend_from_slice(&t);
        }
        pts.extend(vec![0.0; 300 * dim]);
        let mut qs = vec![0.0; dim];
        let mut q2 = vec![0.0; dim];
        q2[3] = 0.25;
        qs.extend(q2);
        qs.extend_from_slice(&pts[1500 * dim..1501 * dim]);
        for &k in &[1usize, 45, 1000] {
            compare(&pts, dim, &qs, k);
        }
    }
}
