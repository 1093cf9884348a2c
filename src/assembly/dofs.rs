//! Free and constrained coordinates.

/// Marker for a constrained coordinate in [`DofMap::free_index`].
const CONSTRAINED: usize = usize::MAX;

/// Map between the full coordinate vector (all nodal coordinates) and the free coordinates that
/// the solvers iterate on. Constrained coordinates keep values set by the model (supports,
/// prescribed motion).
#[derive(Clone, Debug, Default)]
pub struct DofMap {
    free_of: Vec<usize>,
    free_to_full: Vec<usize>,
}

impl DofMap {
    /// `constrained[i]` tells whether full coordinate `i` is constrained.
    pub fn new(constrained: &[bool]) -> Self {
        let mut free_of = vec![CONSTRAINED; constrained.len()];
        let mut free_to_full = Vec::new();
        for (i, &c) in constrained.iter().enumerate() {
            if !c {
                free_of[i] = free_to_full.len();
                free_to_full.push(i);
            }
        }
        Self {
            free_of,
            free_to_full,
        }
    }

    /// Number of full coordinates.
    pub fn n_full(&self) -> usize {
        self.free_of.len()
    }

    /// Number of free coordinates.
    pub fn n_free(&self) -> usize {
        self.free_to_full.len()
    }

    /// Free index of full coordinate `i`, or `None` if it is constrained.
    #[inline]
    pub fn free_index(&self, i: usize) -> Option<usize> {
        let k = self.free_of[i];
        (k != CONSTRAINED).then_some(k)
    }

    /// Full index of each free coordinate.
    pub fn free_to_full(&self) -> &[usize] {
        &self.free_to_full
    }

    /// Writes free values into the full vector (constrained entries untouched).
    pub fn expand(&self, free: &[f64], full: &mut [f64]) {
        for (k, &i) in self.free_to_full.iter().enumerate() {
            full[i] = free[k];
        }
    }

    /// Extracts the free entries of a full vector.
    pub fn restrict(&self, full: &[f64], free: &mut [f64]) {
        for (k, &i) in self.free_to_full.iter().enumerate() {
            free[k] = full[i];
        }
    }
}
