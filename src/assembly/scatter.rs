//! Element-to-global scatter with positions precomputed once per mesh.

use super::dofs::DofMap;
use crate::linalg::CscPattern;
use nalgebra::{SMatrix, SVector};

const NONE: u32 = u32::MAX;

/// The global free–free pattern and, for every element, where each entry of its matrix goes.
#[derive(Clone, Debug)]
pub struct Assembly {
    /// Free/constrained coordinates.
    pub dofs: DofMap,
    /// Pattern of the free–free iteration matrix.
    pub pattern: CscPattern,
    ndof: usize,
    elem_dofs: Vec<usize>,
    elem_pos: Vec<u32>,
}

impl Assembly {
    /// Assembly for elements with `ndof` coordinates each; `element_dofs` lists the full
    /// coordinate indices of every element (length `n_elements · ndof`). Extra couplings
    /// (`extra`, pairs of full indices) can be added for non-element terms.
    pub fn new(
        dofs: DofMap,
        ndof: usize,
        element_dofs: Vec<usize>,
        extra: &[(usize, usize)],
    ) -> Self {
        assert_eq!(element_dofs.len() % ndof.max(1), 0);
        let mut entries = Vec::new();
        for el in element_dofs.chunks(ndof) {
            for &i in el {
                for &j in el {
                    if let (Some(a), Some(b)) = (dofs.free_index(i), dofs.free_index(j)) {
                        entries.push((a, b));
                    }
                }
            }
        }
        for &(i, j) in extra {
            if let (Some(a), Some(b)) = (dofs.free_index(i), dofs.free_index(j)) {
                entries.push((a, b));
                entries.push((b, a));
            }
        }
        let pattern = CscPattern::from_entries(dofs.n_free(), entries);
        let mut elem_pos = Vec::with_capacity(element_dofs.len() * ndof);
        for el in element_dofs.chunks(ndof) {
            for &j in el {
                for &i in el {
                    let p = match (dofs.free_index(i), dofs.free_index(j)) {
                        (Some(a), Some(b)) => pattern.position(a, b).expect("in pattern") as u32,
                        _ => NONE,
                    };
                    elem_pos.push(p);
                }
            }
        }
        Self {
            dofs,
            pattern,
            ndof,
            elem_dofs: element_dofs,
            elem_pos,
        }
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elem_dofs.len() / self.ndof.max(1)
    }

    /// Full coordinate indices of element `e`.
    #[inline]
    pub fn element_dofs(&self, e: usize) -> &[usize] {
        &self.elem_dofs[e * self.ndof..(e + 1) * self.ndof]
    }

    /// Gathers element `e`'s coordinates from a full vector.
    #[inline]
    pub fn gather<const N: usize>(&self, e: usize, full: &[f64]) -> SVector<f64, N> {
        debug_assert_eq!(N, self.ndof);
        let d = self.element_dofs(e);
        SVector::<f64, N>::from_fn(|i, _| full[d[i]])
    }

    /// Adds `scale · f_e` into a full vector.
    #[inline]
    pub fn add_vector<const N: usize>(
        &self,
        e: usize,
        f: &SVector<f64, N>,
        scale: f64,
        full: &mut [f64],
    ) {
        let d = self.element_dofs(e);
        for i in 0..N {
            full[d[i]] += scale * f[i];
        }
    }

    /// Adds `scale · K_e` into the values of the free–free matrix (constrained rows and columns
    /// are skipped).
    #[inline]
    pub fn add_matrix<const N: usize>(
        &self,
        e: usize,
        k: &SMatrix<f64, N, N>,
        scale: f64,
        vals: &mut [f64],
    ) {
        let pos = &self.elem_pos[e * N * N..(e + 1) * N * N];
        for (p, kv) in pos.iter().zip(k.as_slice()) {
            if *p != NONE {
                vals[*p as usize] += scale * kv;
            }
        }
    }

    /// Adds `scale` times a coupling term between full coordinates `i` and `j` (must be in the
    /// pattern through `extra`, an element, or the diagonal).
    pub fn add_entry(&self, i: usize, j: usize, value: f64, vals: &mut [f64]) {
        if let (Some(a), Some(b)) = (self.dofs.free_index(i), self.dofs.free_index(j)) {
            let p = self.pattern.position(a, b).expect("entry in pattern");
            vals[p] += value;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn scatter_skips_constrained_coordinates() {
        // two 2-dof "elements" on a 3-coordinate chain, coordinate 0 constrained
        let dofs = DofMap::new(&[true, false, false]);
        let asm = Assembly::new(dofs, 2, vec![0, 1, 1, 2], &[]);
        assert_eq!(asm.pattern.n(), 2);
        let mut vals = vec![0.0; asm.pattern.nnz()];
        let k = Matrix2::new(1.0, -1.0, -1.0, 1.0);
        asm.add_matrix(0, &k, 1.0, &mut vals);
        asm.add_matrix(1, &k, 2.0, &mut vals);
        let at = |r, c| vals[asm.pattern.position(r, c).unwrap()];
        assert_eq!(at(0, 0), 3.0);
        assert_eq!(at(0, 1), -2.0);
        assert_eq!(at(1, 1), 2.0);
    }
}
