//! The map from a solid's full indices `node·d + component` to its free unknowns, one `u32` an
//! entry (issue 31: 4 bytes where `Option<usize>` takes 16; 12 MiB less on the 69³ cube's
//! explicit run, whose peak is about 230 MiB). A box holds at most 10⁷ cells
//! ([`crate::spec::MAX_ELEMENTS`]) and a mesh file at most 256 MiB
//! ([`crate::mesh_file::MAX_MESH_FILE_BYTES`]), so a scene's unknowns number far below
//! `u32::MAX`, the mark of an eliminated index.

/// Full index → free unknown (None where eliminated).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap(Vec<u32>);

impl DofMap {
    const NONE: u32 = u32::MAX;

    /// The map of `n` full indices of which `dofs` (increasing) are free, `dofs[k]` ↦ k.
    ///
    /// # Panics
    /// If `dofs` holds `u32::MAX` or more unknowns (no scene does: module docs).
    pub fn new(n: usize, dofs: &[usize]) -> Self {
        assert!(dofs.len() < Self::NONE as usize, "{} unknowns: at most {} are indexed", dofs.len(), Self::NONE - 1);
        let mut map = vec![Self::NONE; n];
        for (k, &g) in dofs.iter().enumerate() {
            map[g] = k as u32;
        }
        DofMap(map)
    }

    /// The map of `n` full indices, all free (g ↦ g).
    pub fn identity(n: usize) -> Self {
        assert!(n < Self::NONE as usize, "{n} unknowns: at most {} are indexed", Self::NONE - 1);
        DofMap((0..n as u32).collect())
    }

    /// The free unknown of full index `g`, None where it is eliminated.
    #[inline]
    pub fn get(&self, g: usize) -> Option<usize> {
        let k = self.0[g];
        (k != Self::NONE).then_some(k as usize)
    }

    /// Whether full index `g` is a free unknown.
    #[inline]
    pub fn is_free(&self, g: usize) -> bool {
        self.0[g] != Self::NONE
    }

    /// The number of full indices.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// [`Self::get`] of every full index in order.
    pub fn iter(&self) -> impl Iterator<Item = Option<usize>> + '_ {
        (0..self.0.len()).map(|g| self.get(g))
    }

    /// One flag per full index: whether it is free.
    pub fn flags(&self) -> Vec<bool> {
        self.0.iter().map(|&k| k != Self::NONE).collect()
    }
}
