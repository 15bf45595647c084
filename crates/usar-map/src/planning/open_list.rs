//! The open list of [`super::GridAStar`]: exact A* order at O(1) per operation, no heap and no
//! sorting.
//!
//! A* with a consistent heuristic h is Dijkstra's algorithm on the reduced costs
//! c'(u, v) = c(u, v) + h(v) − h(u) ≥ 0: cells are expanded in non-decreasing f = g + h, and a
//! cell opened from the cell being expanded gets f_new = f_cur + c'(u, v). On a grid with
//! straight cost 1, diagonal cost √2 and the octile heuristic, c' takes only six values,
//! 0, 2 − √2, 2√2 − 2, √2, 2 and 2√2 (with Manhattan and 4-connectivity: 0 and 2). So the open
//! list keeps one FIFO queue per positive value: each receives keys f_cur + c' in the order in
//! which cells are expanded, hence in non-decreasing order, and the least open f is the least of
//! the queue heads (the multi-queue form of Dial's bucket queue, as in Dijkstra with few
//! distinct edge lengths; Ahuja, Mehlhorn, Orlin & Tarjan 1990).
//!
//! Cells opened with c' = 0 have the f being expanded: they go on a stack, popped last-in
//! first-out, so that among equal f the cell just reached, deeper along its path (larger g),
//! comes first. Between the heads of the queues, equal f is broken toward the smaller h (the
//! larger g). This is the tie-breaking that makes A* walk straight at the goal across open
//! floors instead of fanning out over every cell of equal f.
//!
//! A push whose step of f matches none of the classes (impossible with the built-in heuristics,
//! kept as a safety net for exactness) goes to a binary heap that takes part in the comparison.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A first-in first-out queue on a `Vec` with a read index: cheaper than a ring buffer's
/// wrap-around. When the `Vec` is full, a consumed prefix of at least half its length is
/// dropped instead of growing it, so that its memory stays within twice the live size (and in
/// cache).
#[derive(Clone, Debug)]
pub(crate) struct Fifo<T> {
    items: Vec<T>,
    head: usize,
}

impl<T> Default for Fifo<T> {
    fn default() -> Self {
        Self {
            items: Vec::new(),
            head: 0,
        }
    }
}

impl<T: Copy> Fifo<T> {
    pub fn clear(&mut self) {
        self.items.clear();
        self.head = 0;
    }

    #[inline(always)]
    pub fn push(&mut self, item: T) {
        if self.items.len() == self.items.capacity() && 2 * self.head >= self.items.len() {
            self.items.drain(..self.head);
            self.head = 0;
        }
        self.items.push(item);
    }

    #[inline(always)]
    pub fn front(&self) -> Option<&T> {
        self.items.get(self.head)
    }

    #[inline(always)]
    pub fn pop(&mut self) -> Option<T> {
        let item = *self.items.get(self.head)?;
        self.head += 1;
        if self.head == self.items.len() {
            self.clear();
        }
        Some(item)
    }
}

/// The positive steps of f along one move, in cells (see the module documentation).
const F_STEPS: [f64; 5] = [
    2.0 - std::f64::consts::SQRT_2,
    2.0 * std::f64::consts::SQRT_2 - 2.0,
    std::f64::consts::SQRT_2,
    2.0,
    2.0 * std::f64::consts::SQRT_2,
];

/// Tolerance, cells, when matching a step of f to a class, and when deciding that two f values
/// are equal. Distinct values a + b√2 on grids below 10⁵ cells a side differ by more than 1e-6,
/// and rounding in sums of up to 10⁶ steps stays below 1e-9.
const F_TOLERANCE: f64 = 1e-9;

/// An open-list entry, 16 bytes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OpenEntry {
    /// f = g + h, cells.
    pub f: f64,
    /// h, cells, rounded to f32: only used to break ties in f toward the larger g.
    pub h: f32,
    /// Padded index of the cell.
    pub node: u32,
}

impl OpenEntry {
    /// True if `self` should be expanded before `other`: smaller f, or equal f and smaller h.
    #[inline(always)]
    fn precedes(&self, other: &OpenEntry) -> bool {
        if self.f < other.f - F_TOLERANCE {
            true
        } else if self.f > other.f + F_TOLERANCE {
            false
        } else {
            self.h < other.h
        }
    }
}

/// Heap wrapper for the fallback: the max-heap pops the entry that [`OpenEntry::precedes`].
#[derive(Clone, Copy, Debug)]
struct Fallback(OpenEntry);

impl PartialEq for Fallback {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Fallback {}
impl PartialOrd for Fallback {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Fallback {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .0
            .f
            .total_cmp(&self.0.f)
            .then(other.0.h.total_cmp(&self.0.h))
    }
}

/// Where the best head was found.
#[derive(Clone, Copy)]
enum Source {
    Stack,
    Queue(usize),
    Fallback,
}

/// The open list (see the module documentation). Buffers are kept between searches.
#[derive(Clone, Debug, Default)]
pub(crate) struct OpenList {
    /// Entries with the f being expanded (step 0), last-in first-out.
    stack: Vec<OpenEntry>,
    /// One FIFO queue per positive step class of [`F_STEPS`].
    queues: [Fifo<OpenEntry>; 5],
    /// Entries whose step matched no class.
    fallback: BinaryHeap<Fallback>,
    fallback_pushes: usize,
}

impl OpenList {
    pub fn clear(&mut self) {
        self.stack.clear();
        for q in &mut self.queues {
            q.clear();
        }
        self.fallback.clear();
        self.fallback_pushes = 0;
    }

    /// Number of pushes since the last `clear` that went to the fallback heap.
    pub fn fallback_pushes(&self) -> usize {
        self.fallback_pushes
    }

    /// Adds an entry opened while expanding a cell of f = `f_expanded` (the start: its own f).
    #[inline(always)]
    pub fn push(&mut self, entry: OpenEntry, f_expanded: f64) {
        let step = entry.f - f_expanded;
        if step.abs() <= F_TOLERANCE {
            self.stack.push(entry);
            return;
        }
        for (queue, &class) in self.queues.iter_mut().zip(&F_STEPS) {
            if (step - class).abs() <= F_TOLERANCE {
                queue.push(entry);
                return;
            }
        }
        self.fallback_pushes += 1;
        self.fallback.push(Fallback(entry));
    }

    /// Removes and returns the entry to expand next.
    #[inline(always)]
    pub fn pop(&mut self) -> Option<OpenEntry> {
        let mut best: Option<(OpenEntry, Source)> = self.stack.last().map(|&e| (e, Source::Stack));
        for (k, queue) in self.queues.iter().enumerate() {
            if let Some(&head) = queue.front()
                && best.is_none_or(|(b, _)| head.precedes(&b))
            {
                best = Some((head, Source::Queue(k)));
            }
        }
        if !self.fallback.is_empty()
            && let Some(&Fallback(head)) = self.fallback.peek()
            && best.is_none_or(|(b, _)| head.precedes(&b))
        {
            best = Some((head, Source::Fallback));
        }
        let (entry, source) = best?;
        match source {
            Source::Stack => self.stack.pop(),
            Source::Queue(k) => self.queues[k].pop(),
            Source::Fallback => self.fallback.pop().map(|f| f.0),
        };
        Some(entry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(f: f64, h: f32, node: u32) -> OpenEntry {
        OpenEntry { f, h, node }
    }

    #[test]
    fn fifo_keeps_order_across_compaction() {
        let mut fifo = Fifo::default();
        let mut expected = std::collections::VecDeque::new();
        for i in 0..20_000u32 {
            fifo.push(i);
            expected.push_back(i);
            if i % 3 != 0 {
                assert_eq!(fifo.pop(), expected.pop_front());
            }
        }
        while let Some(e) = expected.pop_front() {
            assert_eq!(fifo.front(), Some(&e));
            assert_eq!(fifo.pop(), Some(e));
        }
        assert_eq!(fifo.pop(), None);
    }

    #[test]
    fn pops_least_f_then_least_h_and_stack_last_in_first_out() {
        let mut open = OpenList::default();
        open.push(entry(10.0, 5.0, 0), 10.0);
        open.push(entry(12.0, 3.0, 1), 10.0);
        open.push(entry(10.0 + F_STEPS[0], 1.0, 2), 10.0);
        open.push(entry(10.0, 4.0, 3), 10.0);
        open.push(entry(10.0, 4.0, 4), 10.0);
        let order: Vec<u32> = std::iter::from_fn(|| open.pop()).map(|e| e.node).collect();
        assert_eq!(order, [4, 3, 0, 2, 1]);
        assert_eq!(open.fallback_pushes(), 0);
        open.push(entry(11.0, 1.0, 5), 10.0);
        open.push(entry(10.5, 1.0, 6), 10.0);
        assert_eq!(open.fallback_pushes(), 2);
        assert_eq!(open.pop().map(|e| e.node), Some(6));
        assert_eq!(open.pop().map(|e| e.node), Some(5));
        assert!(open.pop().is_none());
    }
}
