//! Exact Euclidean distance transform (Felzenszwalb & Huttenlocher 2012, "Distance transforms of
//! sampled functions"): for every cell, the squared distance in cells to the nearest blocked
//! cell, the ring of cells just outside the grid counting as blocked.
//!
//! Separable: a 1-D pass down each column gives g(c, r) = min over blocked r' of (r − r')²; a
//! 1-D pass along each row then gives d²(c, r) = min over c' of (c − c')² + g(c', r), the lower
//! envelope of parabolas rooted at (c', g(c', r)). O(cells).

/// Squared distances (in cells²) from each cell of a `width` × `height` row-major grid to the
/// nearest cell where `free` is false or to the outside of the grid.
pub fn squared_edt(free: &[bool], width: usize, height: usize) -> Vec<f32> {
    assert_eq!(free.len(), width * height, "one flag per cell");
    let inf = f32::MAX / 4.0;
    let mut g = vec![0f32; free.len()];
    let n = width.max(height);
    let mut f = vec![0f32; n];
    let mut d = vec![0f32; n];
    let mut v = vec![0usize; n];
    let mut z = vec![0f32; n + 1];
    for col in 0..width {
        for row in 0..height {
            f[row] = if free[row * width + col] { inf } else { 0.0 };
        }
        transform_1d(&f[..height], &mut d[..height], &mut v, &mut z);
        for row in 0..height {
            g[row * width + col] = d[row];
        }
    }
    for row in 0..height {
        f[..width].copy_from_slice(&g[row * width..(row + 1) * width]);
        transform_1d(&f[..width], &mut d[..width], &mut v, &mut z);
        g[row * width..(row + 1) * width].copy_from_slice(&d[..width]);
    }
    g
}

/// d(q) = min over p of (q − p)² + f(p), with blocked sites at −1 and len (f = 0 there).
fn transform_1d(f: &[f32], d: &mut [f32], v: &mut [usize], z: &mut [f32]) {
    let n = f.len();
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f32::NEG_INFINITY;
    z[1] = f32::INFINITY;
    for q in 1..n {
        let fq = f[q] + (q * q) as f32;
        loop {
            let p = v[k];
            let s = (fq - (f[p] + (p * p) as f32)) / (2.0 * (q as f32 - p as f32));
            if s <= z[k] && k > 0 {
                k -= 1;
            } else {
                k += 1;
                v[k] = q;
                z[k] = s;
                z[k + 1] = f32::INFINITY;
                break;
            }
        }
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f32 {
            k += 1;
        }
        let p = v[k];
        let dq = (q as f32 - p as f32).powi(2) + f[p];
        let border = ((q + 1) as f32).powi(2).min(((n - q) as f32).powi(2));
        *out = dq.min(border);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(free: &[bool], w: usize, h: usize) -> Vec<f32> {
        let mut out = vec![0f32; w * h];
        for r in 0..h {
            for c in 0..w {
                let (ci, ri) = (c as i64, r as i64);
                // Border ring.
                let mut best = [ci + 1, w as i64 - ci, ri + 1, h as i64 - ri]
                    .iter()
                    .map(|&x| (x * x) as f32)
                    .fold(f32::MAX, f32::min);
                for r2 in 0..h {
                    for c2 in 0..w {
                        if !free[r2 * w + c2] {
                            let dd = (ci - c2 as i64).pow(2) + (ri - r2 as i64).pow(2);
                            best = best.min(dd as f32);
                        }
                    }
                }
                out[r * w + c] = if free[r * w + c] { best } else { 0.0 };
            }
        }
        out
    }

    #[test]
    fn matches_brute_force_on_a_pseudo_random_grid() {
        let (w, h) = (23, 17);
        let mut x = 12345u64;
        let free: Vec<bool> = (0..w * h)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (x >> 60) != 0
            })
            .collect();
        assert_eq!(squared_edt(&free, w, h), brute(&free, w, h));
    }
}
