//! Boundary editing (method §1: the given nodes are the discretisation, and
//! resampling is a separate, explicit editing tool): a [`Draft`] of loops of
//! points that may be invalid while the user edits it, with the operations
//! of the editor's boundary tools (draw, move, insert, delete, split a
//! segment into k parts, resample a loop to a target size with the
//! even-count rule) and live validation that names the nodes at fault.

use crate::boundary::{Boundary, BoundaryError};
use crate::geom::Point;
use thiserror::Error;

/// Loops of points being edited: `loops[0]` is the outer loop when the
/// draft becomes a boundary (the largest loop is taken as outer whatever
/// the order; orientation is set then).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Draft {
    pub loops: Vec<Vec<Point>>,
}

/// A node of a draft: loop and position in it.
pub type At = (usize, usize);

impl Draft {
    /// The draft of a boundary (its loops in order).
    pub fn of(b: &Boundary) -> Draft {
        Draft {
            loops: b
                .loops
                .iter()
                .map(|l| l.iter().map(|&i| b.points[i]).collect())
                .collect(),
        }
    }

    /// All nodes.
    pub fn node_count(&self) -> usize {
        self.loops.iter().map(Vec::len).sum()
    }

    /// The validated boundary (the checks of [`Boundary::new`]).
    pub fn to_boundary(&self) -> Result<Boundary, BoundaryError> {
        let mut points = Vec::with_capacity(self.node_count());
        let mut loops = Vec::with_capacity(self.loops.len());
        for l in &self.loops {
            let start = points.len();
            points.extend_from_slice(l);
            loops.push((start..points.len()).collect());
        }
        Boundary::new(points, loops, None)
    }

    /// The node with label `label` (1-based over all loops, as
    /// [`Draft::to_boundary`] numbers them).
    fn at_label(&self, label: i64) -> Option<At> {
        let mut k = usize::try_from(label).ok()?.checked_sub(1)?;
        for (li, l) in self.loops.iter().enumerate() {
            if k < l.len() {
                return Some((li, k));
            }
            k -= l.len();
        }
        None
    }

    /// The nodes a validation error is about: the node(s) it names, or
    /// every node of the loop it names.
    pub fn marked(&self, e: &BoundaryError) -> Vec<At> {
        let whole = |li: usize| -> Vec<At> {
            self.loops
                .get(li)
                .map(|l| (0..l.len()).map(|k| (li, k)).collect())
                .unwrap_or_default()
        };
        use BoundaryError as E;
        match *e {
            E::NonFinite { node }
            | E::TooLarge { node, .. }
            | E::OpenChain { node }
            | E::Branching { node, .. }
            | E::DuplicateNode { node, .. }
            | E::FoldBack { node, .. } => self.at_label(node).into_iter().collect(),
            E::Crossing { node_a, node_b, .. } | E::NodesCoincide { node_a, node_b, .. } => {
                [node_a, node_b]
                    .iter()
                    .filter_map(|&n| self.at_label(n))
                    .collect()
            }
            E::NodeOnSegment { node, from, to, .. } => [node, from, to]
                .iter()
                .filter_map(|&n| self.at_label(n))
                .collect(),
            E::LoopTooShort { loop_index, .. }
            | E::ZeroArea { loop_index }
            | E::HoleOutside { loop_index }
            | E::NestedHole { loop_index, .. } => whole(loop_index),
            E::Empty
            | E::TooSmall { .. }
            | E::TooFewNodes { .. }
            | E::BadSegmentIndex { .. }
            | E::OddNodeCount { .. } => Vec::new(),
        }
    }

    /// The node nearest to `p` within `r`.
    pub fn nearest_node(&self, p: Point, r: f64) -> Option<At> {
        let mut best: Option<(f64, At)> = None;
        for (li, l) in self.loops.iter().enumerate() {
            for (k, q) in l.iter().enumerate() {
                let d = q.distance(p);
                if d <= r && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (li, k)));
                }
            }
        }
        best.map(|(_, a)| a)
    }

    /// The segment (from node `k` to the next) nearest to `p` within `r`.
    pub fn nearest_segment(&self, p: Point, r: f64) -> Option<At> {
        let mut best: Option<(f64, At)> = None;
        for (li, l) in self.loops.iter().enumerate() {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                let d = crate::geom::point_segment_distance(p, a, b);
                if d <= r && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (li, k)));
                }
            }
        }
        best.map(|(_, a)| a)
    }

    pub fn move_node(&mut self, (li, k): At, p: Point) {
        if let Some(q) = self.loops.get_mut(li).and_then(|l| l.get_mut(k)) {
            *q = p;
        }
    }

    /// Inserts `p` after node `k` (on segment `k`).
    pub fn insert(&mut self, (li, k): At, p: Point) {
        if let Some(l) = self.loops.get_mut(li) {
            l.insert((k + 1).min(l.len()), p);
        }
    }

    /// Deletes a node; a loop left with no nodes goes.
    pub fn delete(&mut self, (li, k): At) {
        if let Some(l) = self.loops.get_mut(li) {
            if k < l.len() {
                l.remove(k);
            }
            if l.is_empty() {
                self.loops.remove(li);
            }
        }
    }

    /// Splits segment `k` into `parts` equal parts.
    pub fn split(&mut self, (li, k): At, parts: usize) {
        let Some(l) = self.loops.get_mut(li) else {
            return;
        };
        if k >= l.len() || parts < 2 {
            return;
        }
        let (a, b) = (l[k], l[(k + 1) % l.len()]);
        let new: Vec<Point> = (1..parts)
            .map(|j| a + (b - a) * (j as f64 / parts as f64))
            .collect();
        l.splice(k + 1..k + 1, new);
    }

    /// Resamples loop `li` to segments of about `h`: every segment is cut
    /// into `max(1, round(len / h))` equal parts, so the loop's nodes (its
    /// corners) stay. Even-count rule: when the whole draft would then have
    /// an odd node count, the segment whose parts are longest gets one
    /// part more. A target that is not a positive length, a loop that is
    /// not there, or a target so short that the draft would pass
    /// [`MAX_RESAMPLED_NODES`] is refused and the draft left as it was.
    pub fn resample(&mut self, li: usize, h: f64) -> Result<(), ResampleError> {
        let parts = self.resample_parts(li, h)?;
        let l = &mut self.loops[li];
        let n = l.len();
        let mut out = Vec::with_capacity(parts.iter().sum());
        for (k, &m) in parts.iter().enumerate() {
            let (a, b) = (l[k], l[(k + 1) % n]);
            for j in 0..m {
                out.push(a + (b - a) * (j as f64 / m as f64));
            }
        }
        *l = out;
        Ok(())
    }

    /// Every loop resampled to target `h` ([`Draft::resample`] loop after
    /// loop, so the whole draft ends with an even node count); refused as
    /// a whole, the draft left as it was, when any loop is.
    pub fn resample_all(&mut self, h: f64) -> Result<(), ResampleError> {
        let mut d = self.clone();
        for li in 0..d.loops.len() {
            d.resample(li, h)?;
        }
        *self = d;
        Ok(())
    }

    /// The nodes [`Draft::resample_all`] would give the draft (about: one
    /// more per loop at most for an even count), checked as it checks
    /// each loop.
    pub fn resample_all_nodes(&self, h: f64) -> Result<usize, ResampleError> {
        let mut total = 0;
        for li in 0..self.loops.len() {
            total += self.resample_parts(li, h)?.iter().sum::<usize>();
        }
        if total > MAX_RESAMPLED_NODES {
            return Err(ResampleError::TooManyNodes {
                loop_index: self.loops.len().saturating_sub(1),
                h,
                nodes: total as f64,
            });
        }
        Ok(total)
    }

    /// The parts each segment of loop `li` is cut into by
    /// [`Draft::resample`], checked as it checks them.
    pub fn resample_parts(&self, li: usize, h: f64) -> Result<Vec<usize>, ResampleError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(ResampleError::Target(h));
        }
        let l = self.loops.get(li).ok_or(ResampleError::NoLoop {
            loop_index: li,
            loops: self.loops.len(),
        })?;
        let others: usize = self
            .loops
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != li)
            .map(|(_, l)| l.len())
            .sum();
        let n = l.len();
        let seg = |k: usize| (l[k], l[(k + 1) % n]);
        // Counted in floating point first: a target far below the
        // segments would overflow a count of parts.
        let wanted: Vec<f64> = (0..n)
            .map(|k| {
                let (a, b) = seg(k);
                (a.distance(b) / h).round().max(1.0)
            })
            .collect();
        let total = others as f64 + wanted.iter().sum::<f64>() + 1.0;
        if total > MAX_RESAMPLED_NODES as f64 {
            return Err(ResampleError::TooManyNodes {
                loop_index: li,
                h,
                nodes: total,
            });
        }
        // The domain's quads at that size, about: the largest loop's area
        // over h² (a long boundary of few nodes can still enclose far more
        // quads than a mesh can hold).
        let area = self
            .loops
            .iter()
            .map(|l| crate::geom::polygon_area(l.iter().copied()).abs())
            .fold(0.0, f64::max);
        let quads = area / (h * h);
        if quads > MAX_RESAMPLED_QUADS as f64 {
            return Err(ResampleError::TooManyQuads {
                loop_index: li,
                h,
                quads,
            });
        }
        let mut parts: Vec<usize> = wanted.iter().map(|&w| w as usize).collect();
        if (others + parts.iter().sum::<usize>()) % 2 == 1 {
            let longest = (0..n).max_by(|&i, &j| {
                let (a, b) = seg(i);
                let (c, d) = seg(j);
                (a.distance(b) / parts[i] as f64).total_cmp(&(c.distance(d) / parts[j] as f64))
            });
            if let Some(k) = longest {
                parts[k] += 1;
            }
        }
        Ok(parts)
    }
}

/// The most nodes a draft may have after a resample: a boundary of a
/// million nodes is already far past what a mesh of it could hold in
/// memory (a disk of n nodes takes about n²/(4π) quads).
pub const MAX_RESAMPLED_NODES: usize = 1_000_000;

/// The most quads a resample may ask of the domain (its area over the
/// target squared): 10 million, about four times the largest benchmark
/// disk's mesh.
pub const MAX_RESAMPLED_QUADS: usize = 10_000_000;

/// Why a resample was refused.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum ResampleError {
    #[error("resample target {0} is not a positive length")]
    Target(f64),
    #[error("there is no loop {loop_index} to resample (the draft has {loops})")]
    NoLoop { loop_index: usize, loops: usize },
    #[error("resampling loop {loop_index} to segments of {h:.3e} would give the boundary about {nodes:.3e} nodes, more than {max}", max = MAX_RESAMPLED_NODES)]
    TooManyNodes {
        loop_index: usize,
        h: f64,
        nodes: f64,
    },
    #[error("resampling loop {loop_index} to segments of {h:.3e} would ask for about {quads:.3e} quads inside, more than {max}", max = MAX_RESAMPLED_QUADS)]
    TooManyQuads {
        loop_index: usize,
        h: f64,
        quads: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Draft {
        Draft {
            loops: vec![vec![
                Point::new(0.0, 0.0),
                Point::new(1.0, 0.0),
                Point::new(1.0, 1.0),
                Point::new(0.0, 1.0),
            ]],
        }
    }

    #[test]
    fn a_square_round_trips_and_edits_stay_valid() {
        let d = square();
        let b = d.to_boundary().unwrap();
        assert_eq!(Draft::of(&b).node_count(), 4);
        let mut e = d.clone();
        e.split((0, 0), 3);
        assert_eq!(e.loops[0][1], Point::new(1.0 / 3.0, 0.0));
        // 6 nodes: even, valid.
        e.to_boundary().unwrap();
        e.insert((0, 3), Point::new(1.0, 0.5));
        assert!(matches!(
            e.to_boundary(),
            Err(BoundaryError::OddNodeCount { count: 7 })
        ));
        e.delete((0, 4));
        e.to_boundary().unwrap();
    }

    #[test]
    fn resampling_keeps_corners_and_makes_the_count_even() {
        let mut d = square();
        d.resample(0, 0.3).unwrap();
        // round(1 / 0.3) = 3 parts a side: 12 nodes, corners kept.
        assert_eq!(d.node_count(), 12);
        assert_eq!(d.loops[0][3], Point::new(1.0, 0.0));
        let mut t = Draft {
            loops: vec![vec![
                Point::new(0.0, 0.0),
                Point::new(2.0, 0.0),
                Point::new(0.0, 1.0),
            ]],
        };
        t.resample(0, 0.5).unwrap();
        assert_eq!(t.node_count() % 2, 0);
        t.to_boundary().unwrap();
    }

    #[test]
    fn a_resample_past_the_node_bound_is_refused_and_changes_nothing() {
        let mut d = square();
        let e = d.resample(0, 1e-9).unwrap_err();
        assert!(
            matches!(e, ResampleError::TooManyNodes { loop_index: 0, .. }),
            "{e}"
        );
        assert_eq!(d, square());
        // A target that overflows a count of parts is refused the same way.
        assert!(matches!(
            d.resample(0, 1e-300),
            Err(ResampleError::TooManyNodes { .. })
        ));
        for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(d.resample(0, h), Err(ResampleError::Target(_))));
        }
        assert_eq!(
            d.resample(3, 0.5),
            Err(ResampleError::NoLoop {
                loop_index: 3,
                loops: 1
            })
        );
        assert_eq!(d, square());
        // Few nodes around a large area: refused for the quads inside.
        let e = d.resample(0, 1e-4).unwrap_err();
        assert!(matches!(e, ResampleError::TooManyQuads { .. }), "{e}");
        assert_eq!(d, square());
        // A sliver 1e-9 high: just under the node bound is allowed (two
        // sides of 499,998 parts and two of one, with room for the part
        // an odd count would add).
        let mut thin = Draft {
            loops: vec![vec![
                Point::new(0.0, 0.0),
                Point::new(1.0, 0.0),
                Point::new(1.0, 1e-9),
                Point::new(0.0, 1e-9),
            ]],
        };
        assert!(matches!(
            thin.clone().resample(0, 1.0 / 500_001.0),
            Err(ResampleError::TooManyNodes { .. })
        ));
        thin.resample(0, 1.0 / 499_998.0).unwrap();
        assert_eq!(thin.node_count(), 2 * 499_998 + 2);
    }

    #[test]
    fn validation_marks_the_nodes_at_fault() {
        // A bow tie: the loop crosses itself.
        let d = Draft {
            loops: vec![vec![
                Point::new(0.0, 0.0),
                Point::new(1.0, 1.0),
                Point::new(1.0, 0.0),
                Point::new(0.0, 1.0),
            ]],
        };
        let e = d.to_boundary().unwrap_err();
        let marked = d.marked(&e);
        assert!(!marked.is_empty(), "{e}");
        assert!(marked.iter().all(|&(l, k)| l == 0 && k < 4));
        assert_eq!(d.nearest_node(Point::new(0.9, 0.95), 0.2), Some((0, 1)));
        assert_eq!(
            square().nearest_segment(Point::new(0.5, -0.05), 0.1),
            Some((0, 0))
        );
    }
}
