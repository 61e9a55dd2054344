//! Banded LU with partial pivoting on a reverse Cuthill–McKee ordering: the solver of step
//! Jacobians whose pattern is a narrow band once reordered — chains, lattices, periodic rings
//! (a ring's cyclic band becomes a band of twice its width), several coordinate arrays coupled
//! element by element. The ordering and the band are computed once per run from the pattern;
//! a factorization is `O(n (k_l + k_u) k_l)` and a solve `O(n (2 k_l + k_u))` with no fill
//! outside the band and no symbolic work, where a general sparse LU pays for its elimination
//! tree and indirect addressing on every factorization and solve.
//!
//! The elimination is LAPACK's `gbtrf` in row storage: partial pivoting within the `k_l` rows
//! below the diagonal, the upper band widened to `k_u + k_l` for the rows a pivot brings up,
//! row interchanges applied to the columns right of the pivot only (the multipliers stay where
//! they were computed, and a solve applies interchange and multipliers column by column).

use super::{FactorError, HagerCache, LinearSolver};

/// The reverse Cuthill–McKee ordering of the symmetric closure of the pattern `(col_ptr,
/// row_idx)` of an `n × n` matrix: `order[new] = old`. Each connected component is ordered by
/// a breadth-first search from a pseudo-peripheral node (the end of a first search), neighbours
/// by increasing degree, and the whole order reversed.
pub fn reverse_cuthill_mckee(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Vec<usize> {
    // The symmetric adjacency, without the diagonal.
    let mut degree = vec![0usize; n];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                degree[r] += 1;
                degree[c] += 1;
            }
        }
    }
    let mut start = vec![0usize; n + 1];
    for i in 0..n {
        start[i + 1] = start[i] + degree[i];
    }
    let mut fill = start.clone();
    let mut adjacent = vec![0usize; start[n]];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                adjacent[fill[r]] = c;
                fill[r] += 1;
                adjacent[fill[c]] = r;
                fill[c] += 1;
            }
        }
    }
    for i in 0..n {
        let list = &mut adjacent[start[i]..start[i + 1]];
        list.sort_unstable();
        // Duplicates (an entry and its transpose both stored) count once.
        let mut w = 0;
        for k in 0..list.len() {
            if k == 0 || list[k] != list[k - 1] {
                list[w] = list[k];
                w += 1;
            }
        }
        degree[i] = w;
    }
    let neighbours = |i: usize| &adjacent[start[i]..start[i] + degree[i]];
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    let mut level_of = vec![usize::MAX; n];
    // A breadth-first search from `root` over unseen nodes: the nodes in order (marked seen
    // only when `mark`), for the pseudo-peripheral search and for the ordering.
    let bfs = |root: usize, seen: &mut Vec<bool>, level_of: &mut Vec<usize>, mark: bool| {
        let mut queue = vec![root];
        let mut visited = vec![root];
        level_of[root] = 0;
        let mut head = 0;
        while head < queue.len() {
            let i = queue[head];
            head += 1;
            let mut next: Vec<usize> = neighbours(i)
                .iter()
                .copied()
                .filter(|&j| !seen[j] && level_of[j] == usize::MAX)
                .collect();
            next.sort_by_key(|&j| (degree[j], j));
            for j in next {
                level_of[j] = level_of[i] + 1;
                queue.push(j);
                visited.push(j);
            }
        }
        for &i in &visited {
            if mark {
                seen[i] = true;
            }
        }
        let last = *queue.last().expect("the root");
        let depth = level_of[last];
        for &i in &visited {
            level_of[i] = usize::MAX;
        }
        (queue, last, depth)
    };
    for root in 0..n {
        if seen[root] {
            continue;
        }
        // The lowest-degree node of the component, then the far end of a search from it.
        let (component, _, _) = bfs(root, &mut seen, &mut level_of, false);
        let low = *component
            .iter()
            .min_by_key(|&&i| (degree[i], i))
            .expect("the root");
        let (_, far, _) = bfs(low, &mut seen, &mut level_of, false);
        let (queue, _, _) = bfs(far, &mut seen, &mut level_of, true);
        order.extend(queue);
    }
    order.reverse();
    order
}

/// The lower and upper bandwidths of the pattern under `inverse` (`inverse[old] = new`).
pub fn bandwidths(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
    inverse: &[usize],
) -> (usize, usize) {
    let (mut kl, mut ku) = (0, 0);
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            let (r, c) = (inverse[r], inverse[c]);
            if r > c {
                kl = kl.max(r - c);
            } else {
                ku = ku.max(c - r);
            }
        }
    }
    (kl, ku)
}

/// Banded LU with partial pivoting on a reverse Cuthill–McKee ordering of a pattern known at
/// run time (see the [module documentation](self)). Vectors are `DVector`s and the matrix its
/// values in the pattern's CSC order, as for [`super::DynSparseLu`].
pub struct BandedLu {
    n: usize,
    kl: usize,
    ku: usize,
    /// Stored entries per row: `kl` multipliers, the diagonal, `ku + kl` above it.
    width: usize,
    /// `order[new] = old`, `inverse[old] = new`.
    order: Vec<usize>,
    inverse: Vec<usize>,
    col_ptr: Vec<usize>,
    /// Where each CSC entry goes in `band`.
    map: Vec<usize>,
    /// Row `i` holds columns `i − kl ..= i + ku + kl` at `i · width + (j + kl − i)`.
    band: Vec<f64>,
    pivots: Vec<usize>,
    /// `1 / U_ii`: a solve multiplies (a division's latency would lengthen the substitution's
    /// serial chain).
    inverse_diagonal: Vec<f64>,
    work: Vec<f64>,
    hager: HagerCache,
    norm1: f64,
    factored: bool,
}

impl std::fmt::Debug for BandedLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        super::debug_solver(
            f,
            "BandedLu",
            self.n,
            &[("kl", &self.kl), ("ku", &self.ku)],
            self.factored,
        )
    }
}

impl BandedLu {
    /// The solver for `n × n` matrices of the pattern `(col_ptr, row_idx)` (sorted, distinct rows
    /// per column), reordered by reverse Cuthill–McKee.
    ///
    /// # Panics
    /// If the band's storage (`n (2 k_l + k_u + 1)` entries) cannot be allocated; see
    /// [`Self::within`] for a solver built only when its band is narrow and fits.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        Self::within(n, col_ptr, row_idx, usize::MAX)
            .expect("dirac: the banded LU's storage could not be allocated")
    }

    /// The solver when the reordered band is at most `max_width` wide (`k_l + k_u`) and its
    /// storage can be allocated; `None` otherwise, before anything of the band's size is
    /// allocated (the ordering and the bandwidths cost `O(nnz)`).
    pub fn within(
        n: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        max_width: usize,
    ) -> Option<Self> {
        let order = reverse_cuthill_mckee(n, col_ptr, row_idx);
        let mut inverse = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let (kl, ku) = bandwidths(n, col_ptr, row_idx, &inverse);
        if kl + ku > max_width {
            return None;
        }
        let width = 2 * kl + ku + 1;
        let mut band = Vec::new();
        band.try_reserve_exact(n.checked_mul(width)?).ok()?;
        band.resize(n * width, 0.0);
        let mut map = Vec::with_capacity(row_idx.len());
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                let (r, c) = (inverse[r], inverse[c]);
                map.push(r * width + (c + kl - r));
            }
        }
        Some(Self {
            n,
            kl,
            ku,
            width,
            order,
            inverse,
            col_ptr: col_ptr.to_vec(),
            map,
            band,
            pivots: vec![0; n],
            inverse_diagonal: vec![0.0; n],
            work: vec![0.0; n],
            hager: HagerCache::new(n),
            norm1: 0.0,
            factored: false,
        })
    }

    /// The lower and upper bandwidths of the reordered pattern.
    pub fn bandwidths(&self) -> (usize, usize) {
        (self.kl, self.ku)
    }

    /// Entry `(i, j)` of the reordered working matrix (`j` within row `i`'s stored band).
    #[inline(always)]
    fn at(&self, i: usize, j: usize) -> usize {
        i * self.width + (j + self.kl - i)
    }

    /// Solves `A x = b` (or `Aᵀ x = b`) in place. (Index loops: the band's entries are addressed
    /// by row and column, as in LAPACK's `gbtrs`.)
    #[allow(clippy::needless_range_loop)]
    fn solve_slice(&mut self, x: &mut [f64], transpose: bool) {
        debug_assert!(self.factored, "solve before factor");
        let (n, kl, upper) = (self.n, self.kl, self.ku + self.kl);
        let mut y = std::mem::take(&mut self.work);
        for (old, &v) in x.iter().enumerate() {
            y[self.inverse[old]] = v;
        }
        if !transpose {
            let (w, band) = (self.width, &self.band);
            // L: the interchange of column c, then its multipliers (entry (r, c) of row r sits
            // `w − 1` after entry (r − 1, c)).
            for c in 0..n {
                let p = self.pivots[c];
                if p != c {
                    y.swap(c, p);
                }
                let yc = y[c];
                if yc != 0.0 {
                    let end = (c + kl + 1).min(n);
                    for (k, r) in (c + 1..end).enumerate() {
                        y[r] -= band[(c + 1) * w + kl - 1 + k * (w - 1)] * yc;
                    }
                }
            }
            // U: row i's entries right of the diagonal are contiguous. The sum runs from the far
            // end, so `y[i + 1]`, the value just computed, enters last: the substitution's
            // serial chain per row is one product, one sum and one scaling.
            for i in (0..n).rev() {
                let m = (i + upper + 1).min(n) - (i + 1);
                let start = i * w + kl;
                let dot: f64 = band[start + 1..start + 1 + m]
                    .iter()
                    .zip(&y[i + 1..i + 1 + m])
                    .rev()
                    .map(|(a, b)| a * b)
                    .sum();
                y[i] = (y[i] - dot) * self.inverse_diagonal[i];
            }
        } else {
            // Uᵀ.
            for i in 0..n {
                let mut s = y[i];
                for j in i.saturating_sub(upper)..i {
                    s -= self.band[self.at(j, i)] * y[j];
                }
                y[i] = s / self.band[self.at(i, i)];
            }
            // Lᵀ, column by column from the last, then the interchange.
            for c in (0..n).rev() {
                let mut s = y[c];
                for r in c + 1..(c + kl + 1).min(n) {
                    s -= self.band[self.at(r, c)] * y[r];
                }
                y[c] = s;
                let p = self.pivots[c];
                if p != c {
                    y.swap(c, p);
                }
            }
        }
        for (new, &old) in self.order.iter().enumerate() {
            x[old] = y[new];
        }
        self.work = y;
    }
}

impl LinearSolver for BandedLu {
    type Vector = nalgebra::DVector<f64>;
    type Matrix = Vec<f64>;

    fn factor(&mut self, j: &Vec<f64>) -> Result<(), FactorError> {
        self.norm1 = self.hager.refactor(&mut self.factored, &self.col_ptr, j)?;
        self.band.fill(0.0);
        for (&p, &v) in self.map.iter().zip(j.iter()) {
            self.band[p] += v;
        }
        let (n, kl, upper) = (self.n, self.kl, self.ku + self.kl);
        for c in 0..n {
            let last = (c + kl).min(n - 1);
            let mut p = c;
            let mut best = self.band[self.at(c, c)].abs();
            for r in c + 1..=last {
                let v = self.band[self.at(r, c)].abs();
                if v > best {
                    best = v;
                    p = r;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return Err(FactorError::Singular);
            }
            self.pivots[c] = p;
            let right = (c + upper).min(n - 1);
            if p != c {
                for k in c..=right {
                    let (a, b) = (self.at(c, k), self.at(p, k));
                    self.band.swap(a, b);
                }
            }
            let pivot = self.band[self.at(c, c)];
            self.inverse_diagonal[c] = 1.0 / pivot;
            for r in c + 1..=last {
                let at_rc = self.at(r, c);
                let l = self.band[at_rc] / pivot;
                self.band[at_rc] = l;
                if l != 0.0 {
                    for k in c + 1..=right {
                        let (a, b) = (self.at(r, k), self.at(c, k));
                        self.band[a] -= l * self.band[b];
                    }
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    dvector_solves!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::DynSparseLu;
    use nalgebra::{DMatrix, DVector};

    /// The pattern of a periodic lattice of `n` sites with `arrays` coordinate arrays coupled
    /// site by site (array-major order: not banded before reordering), and values.
    fn ring(n: usize, arrays: usize, seed: f64) -> (usize, Vec<usize>, Vec<usize>, Vec<f64>) {
        let dim = n * arrays;
        let mut dense = DMatrix::<f64>::zeros(dim, dim);
        for i in 0..n {
            for a in 0..arrays {
                for b in 0..arrays {
                    for d in [n - 1, 0, 1] {
                        let j = (i + d) % n;
                        let v = ((i * 31 + j * 17 + a * 7 + b * 3) as f64 * seed).sin();
                        dense[(a * n + i, b * n + j)] += 0.3 * v;
                    }
                }
            }
        }
        for i in 0..dim {
            // Small diagonal entries in places, so that pivoting is exercised.
            dense[(i, i)] += if i % 5 == 0 { 1e-3 } else { 2.0 };
        }
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for c in 0..dim {
            for r in 0..dim {
                if dense[(r, c)] != 0.0 {
                    row_idx.push(r);
                    values.push(dense[(r, c)]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (dim, col_ptr, row_idx, values)
    }

    #[test]
    fn a_ring_of_several_arrays_becomes_a_narrow_band() {
        let (dim, col_ptr, row_idx, _) = ring(200, 2, 0.37);
        let lu = BandedLu::new(dim, &col_ptr, &row_idx);
        let (kl, ku) = lu.bandwidths();
        // Two arrays coupled on a ring: a band of a few times the stencil's, whatever n.
        assert!(kl <= 8 && ku <= 8, "{kl}, {ku}");
    }

    #[test]
    fn solves_and_transposed_solves_match_the_sparse_lu() {
        for (n, arrays, seed) in [(7, 1, 0.3), (50, 1, 0.7), (64, 3, 0.11), (300, 2, 1.3)] {
            let (dim, col_ptr, row_idx, values) = ring(n, arrays, seed);
            let mut banded = BandedLu::new(dim, &col_ptr, &row_idx);
            let mut sparse = DynSparseLu::new(dim, col_ptr.clone(), row_idx.clone());
            banded.factor(&values).unwrap();
            sparse.factor(&values).unwrap();
            let b = DVector::from_fn(dim, |i, _| (i as f64 * 0.7).cos());
            let (x, y) = (banded.solve(&b), sparse.solve(&b));
            let err = (&x - &y).amax() / y.amax();
            assert!(err < 1e-12, "n = {n}, arrays = {arrays}: {err:e}");
            let mut xt = b.clone();
            banded.solve_slice(xt.as_mut_slice(), true);
            let mut yt = b.clone();
            sparse.solve_transpose_in_place(&mut yt);
            let err = (&xt - &yt).amax() / yt.amax();
            assert!(err < 1e-12, "transposed, n = {n}: {err:e}");
            let (rb, rs) = (banded.rcond(), sparse.rcond());
            assert!((rb / rs - 1.0).abs() < 0.5, "rcond {rb} vs {rs}");
        }
    }

    #[test]
    fn a_wide_band_is_declined_before_its_storage_is_allocated() {
        // Every pair coupled (a cluster's pattern): the band is the whole matrix.
        let n = 600;
        let col_ptr: Vec<usize> = (0..=n).map(|c| c * n).collect();
        let row_idx: Vec<usize> = (0..n).flat_map(|_| 0..n).collect();
        assert!(BandedLu::within(n, &col_ptr, &row_idx, 16).is_none());
        // A ring is kept.
        let (dim, col_ptr, row_idx, _) = ring(3000, 1, 0.2);
        assert!(BandedLu::within(dim, &col_ptr, &row_idx, 16).is_some());
    }

    #[test]
    fn a_singular_matrix_is_refused() {
        let (dim, col_ptr, row_idx, mut values) = ring(20, 1, 0.5);
        // Column 3 zero.
        for v in &mut values[col_ptr[3]..col_ptr[4]] {
            *v = 0.0;
        }
        let mut lu = BandedLu::new(dim, &col_ptr, &row_idx);
        assert_eq!(lu.factor(&values), Err(FactorError::Singular));
        values[0] = f64::NAN;
        assert_eq!(lu.factor(&values), Err(FactorError::NonFinite));
    }
}
