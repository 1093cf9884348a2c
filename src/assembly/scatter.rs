//! The global free–free pattern of the iteration matrix, built once per mesh from groups of
//! coupled coordinates (elements, element plus pulley angle, ...).

use super::dofs::DofMap;
use crate::linalg::CscPattern;

/// Free/constrained coordinates and the pattern of the free–free iteration matrix. Element
/// sets and coupling blocks precompute their scatter positions in it
/// ([`super::Connectivity`], [`super::ElementSet`]).
#[derive(Clone, Debug)]
pub struct Assembly {
    /// Free/constrained coordinates.
    pub dofs: DofMap,
    /// Pattern of the free–free iteration matrix.
    pub pattern: CscPattern,
}

impl Assembly {
    /// Pattern of `groups`, each `(n, indices)` with `indices` listing the full coordinate
    /// indices of consecutive groups of `n` mutually coupled coordinates (elements of
    /// different sizes in one model give several groups), plus extra couplings `extra`
    /// (pairs of full indices, added symmetrically) for non-element terms.
    pub fn new(dofs: DofMap, groups: &[(usize, &[usize])], extra: &[(usize, usize)]) -> Self {
        let mut entries = Vec::new();
        for &(n, indices) in groups {
            assert_eq!(indices.len() % n.max(1), 0);
            for el in indices.chunks(n.max(1)) {
                for &i in el {
                    for &j in el {
                        if let (Some(a), Some(b)) = (dofs.free_index(i), dofs.free_index(j)) {
                            entries.push((a, b));
                        }
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
        Self { dofs, pattern }
    }

    /// Adds `value` to the coupling between full coordinates `i` and `j` (must be in the
    /// pattern through `extra`, a group, or the diagonal); skipped if either is constrained.
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
    use crate::assembly::Connectivity;
    use nalgebra::Matrix2;

    #[test]
    fn scatter_skips_constrained_coordinates() {
        // two 2-dof "elements" on a 3-coordinate chain, coordinate 0 constrained
        let dofs = DofMap::new(&[true, false, false]);
        let asm = Assembly::new(dofs, &[(2, &[0, 1, 1, 2])], &[]);
        let conn = Connectivity::new(vec![[0, 1], [1, 2]], &asm);
        assert_eq!(asm.pattern.n(), 2);
        let mut vals = vec![0.0; asm.pattern.nnz()];
        let k = Matrix2::new(1.0, -1.0, -1.0, 1.0);
        conn.add_matrix(0, &k, 1.0, &mut vals);
        conn.add_matrix(1, &k, 2.0, &mut vals);
        let at = |r, c| vals[asm.pattern.position(r, c).unwrap()];
        assert_eq!(at(0, 0), 3.0);
        assert_eq!(at(0, 1), -2.0);
        assert_eq!(at(1, 1), 2.0);
    }

    /// Groups of different sizes in one pattern: a 2-coordinate chain element and a
    /// 3-coordinate block coupling its end to an extra coordinate.
    #[test]
    fn groups_of_different_sizes_share_one_pattern() {
        let dofs = DofMap::new(&[false; 4]);
        let asm = Assembly::new(dofs, &[(2, &[0, 1]), (3, &[1, 2, 3])], &[]);
        let a = Connectivity::new(vec![[0, 1]], &asm);
        let b = Connectivity::new(vec![[1, 2, 3]], &asm);
        let mut vals = vec![0.0; asm.pattern.nnz()];
        a.add_matrix(0, &Matrix2::from_element(1.0), 1.0, &mut vals);
        b.add_matrix(0, &nalgebra::Matrix3::from_element(10.0), 1.0, &mut vals);
        let at = |r, c| vals[asm.pattern.position(r, c).unwrap()];
        assert_eq!(at(1, 1), 11.0);
        assert_eq!(at(0, 1), 1.0);
        assert_eq!(at(3, 1), 10.0);
        assert!(asm.pattern.position(0, 3).is_none());
    }
}
