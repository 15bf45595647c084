//! Passability packed one bit per cell, by padded rows and, transposed, by padded columns: the
//! straight jumps of jump point search test 64 cells per step with it.
//!
//! This is the block-based scanning of Harabor & Grastien 2014 ("Improving Jump Point Search"),
//! under the no-corner-cutting rule of `jump_point.rs`: scanning a line (a row, or a column
//! of the transposed bits) in one direction, a cell stops the jump when it is blocked or when a
//! cell beside it, on the line above or below, is passable while the cell behind that one is
//! blocked (a forced neighbour). With `b` the line's bits, `u` and `d` the lines beside it and
//! `u'`, `d'` the same lines shifted by one cell against the direction of travel, the stopping
//! cells of a word are `!b | (u & !u') | (d & !d')`: one word covers 64 cells.

use super::nav_grid::PASSABLE;

/// A bit matrix: `lines` lines of `words_per_line` words, bit `p % 64` of word `p / 64` of a
/// line is position `p` (1 = passable). Bits past the last position are 0 (blocked).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BitLines {
    words_per_line: usize,
    words: Vec<u64>,
}

impl BitLines {
    /// The rows of a padded byte grid of `stride` cells a row (`transpose` false), or its columns
    /// (`transpose` true).
    pub fn from_cells(cells: &[u8], stride: usize, transpose: bool) -> Self {
        let stride = stride.max(1);
        let rows = cells.len() / stride;
        let (lines, positions) = if transpose {
            (stride, rows)
        } else {
            (rows, stride)
        };
        let words_per_line = positions.div_ceil(64);
        let mut words = vec![0u64; lines * words_per_line];
        let bit = |c: u8| u64::from(c == PASSABLE);
        if transpose {
            // 64 rows at a time: their bytes (64 cache lines) stay in cache while every column's
            // word is gathered, and each word is written once.
            for (block, block_cells) in cells.chunks(64 * stride).enumerate() {
                for col in 0..stride {
                    let mut word = 0u64;
                    for (j, row_cells) in block_cells.chunks_exact(stride).enumerate() {
                        word |= bit(row_cells[col]) << j;
                    }
                    words[col * words_per_line + block] = word;
                }
            }
        } else {
            for (row_cells, line) in cells
                .chunks_exact(stride)
                .zip(words.chunks_exact_mut(words_per_line))
            {
                for (chunk, word) in row_cells.chunks(64).zip(line.iter_mut()) {
                    *word = chunk
                        .iter()
                        .enumerate()
                        .fold(0, |w, (j, &c)| w | bit(c) << j);
                }
            }
        }
        Self {
            words_per_line,
            words,
        }
    }

    #[inline(always)]
    fn line(&self, line: usize) -> &[u64] {
        &self.words[line * self.words_per_line..(line + 1) * self.words_per_line]
    }

    /// Sets position `pos` of `line` passable (`true`) or blocked.
    #[inline]
    pub fn set(&mut self, line: usize, pos: usize, passable: bool) {
        let word = &mut self.words[line * self.words_per_line + pos / 64];
        let bit = 1u64 << (pos % 64);
        if passable {
            *word |= bit;
        } else {
            *word &= !bit;
        }
    }

    /// True if position `pos` of `line` is passable.
    #[inline(always)]
    pub fn is_set(&self, line: usize, pos: usize) -> bool {
        self.words[line * self.words_per_line + pos / 64] >> (pos % 64) & 1 == 1
    }

    /// The first position after `from` on `line` (0 < `line` < lines − 1) that is blocked or has
    /// a forced neighbour when moving towards larger positions. Ends at the blocked border.
    #[inline]
    pub fn scan_forward(&self, line: usize, from: usize) -> usize {
        let (b, u, d) = (self.line(line), self.line(line + 1), self.line(line - 1));
        let start = from + 1;
        let mut w = start / 64;
        let mut mask = !0u64 << (start % 64);
        while w < b.len() {
            // Bit p of `*_behind` holds position p − 1.
            let carry = |l: &[u64]| if w > 0 { l[w - 1] >> 63 } else { 0 };
            let u_behind = (u[w] << 1) | carry(u);
            let d_behind = (d[w] << 1) | carry(d);
            let stop = (!b[w] | (u[w] & !u_behind) | (d[w] & !d_behind)) & mask;
            if stop != 0 {
                return w * 64 + stop.trailing_zeros() as usize;
            }
            w += 1;
            mask = !0;
        }
        // Unreachable on a padded grid (its border is blocked); stop at the line's end.
        b.len() * 64
    }

    /// The first position before `from` (> 0) on `line` (0 < `line` < lines − 1) that is
    /// blocked or has a forced neighbour when moving towards smaller positions.
    #[inline]
    pub fn scan_backward(&self, line: usize, from: usize) -> usize {
        let (b, u, d) = (self.line(line), self.line(line + 1), self.line(line - 1));
        let start = from - 1;
        let mut w = start / 64;
        let mut mask = !0u64 >> (63 - start % 64);
        loop {
            // Bit p of `*_behind` holds position p + 1.
            let carry = |l: &[u64]| if w + 1 < l.len() { l[w + 1] << 63 } else { 0 };
            let u_behind = (u[w] >> 1) | carry(u);
            let d_behind = (d[w] >> 1) | carry(d);
            let stop = (!b[w] | (u[w] & !u_behind) | (d[w] & !d_behind)) & mask;
            if stop != 0 {
                return w * 64 + 63 - stop.leading_zeros() as usize;
            }
            if w == 0 {
                // Unreachable on a padded grid (position 0 is the blocked border).
                return 0;
            }
            w -= 1;
            mask = !0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The byte-by-byte definition of a stop, for comparison.
    fn stops(cells: &[u8], stride: usize, row: usize, col: usize, dir: isize) -> bool {
        let at = |r: usize, c: isize| cells[r * stride + c as usize] == PASSABLE;
        let c = col as isize;
        !at(row, c)
            || (at(row + 1, c) && !at(row + 1, c - dir))
            || (at(row - 1, c) && !at(row - 1, c - dir))
    }

    #[test]
    fn scans_agree_with_the_cell_by_cell_rule_in_both_layouts() {
        // 150 × 129 cells (three words a row, three a column) in a pseudo-random pattern.
        let (stride, rows) = (152usize, 131usize);
        let mut state = 12345u64;
        let mut cells = vec![0u8; stride * rows];
        for r in 1..rows - 1 {
            for c in 1..stride - 1 {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                cells[r * stride + c] = u8::from(state >> 61 != 0);
            }
        }
        let by_rows = BitLines::from_cells(&cells, stride, false);
        let by_cols = BitLines::from_cells(&cells, stride, true);
        for r in 1..rows - 1 {
            for c in 1..stride - 1 {
                assert_eq!(by_rows.is_set(r, c), cells[r * stride + c] == PASSABLE);
                assert_eq!(by_cols.is_set(c, r), cells[r * stride + c] == PASSABLE);
                let forward = (c + 1..stride)
                    .find(|&p| stops(&cells, stride, r, p, 1))
                    .unwrap();
                assert_eq!(by_rows.scan_forward(r, c), forward, "row {r} col {c}");
                let backward = (0..c)
                    .rev()
                    .find(|&p| stops(&cells, stride, r, p, -1))
                    .unwrap();
                assert_eq!(by_rows.scan_backward(r, c), backward, "row {r} col {c}");
            }
        }
        // Columns: transpose the bytes and compare the row scans.
        let mut transposed = vec![0u8; stride * rows];
        for r in 0..rows {
            for c in 0..stride {
                transposed[c * rows + r] = cells[r * stride + c];
            }
        }
        let rows_of_transposed = BitLines::from_cells(&transposed, rows, false);
        for c in 1..stride - 1 {
            for r in 1..rows - 1 {
                assert_eq!(
                    by_cols.scan_forward(c, r),
                    rows_of_transposed.scan_forward(c, r)
                );
                assert_eq!(
                    by_cols.scan_backward(c, r),
                    rows_of_transposed.scan_backward(c, r)
                );
            }
        }
    }
}
