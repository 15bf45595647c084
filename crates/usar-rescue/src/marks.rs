//! Per-cell marks cleared in O(1): each search takes a new stamp, and a cell is marked when it
//! holds the current one (the whole array is reset only when the stamp wraps around).

#[derive(Clone, Debug)]
pub(crate) struct Marks {
    marks: Vec<u32>,
    stamp: u32,
}

impl Marks {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            marks: vec![0; n],
            stamp: 0,
        }
    }

    /// Unmarks every cell (a new stamp).
    #[inline]
    pub(crate) fn clear(&mut self) {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.marks.fill(0);
            self.stamp = 1;
        }
    }

    #[inline]
    pub(crate) fn mark(&mut self, i: usize) {
        self.marks[i] = self.stamp;
    }

    #[inline]
    pub(crate) fn is_marked(&self, i: usize) -> bool {
        self.marks[i] == self.stamp
    }
}
