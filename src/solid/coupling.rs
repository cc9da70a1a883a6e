//! The change of variables of a pair's contact (`super::pair`): in node i's frame its normal
//! unknown u'_i,0 = ν_i · u_i is replaced by `w_i = u'_i,0 − Σ_k Σ_c N_k (R_kᵀ ν_i)_c u'_k,c`
//! (= d_i − g_i), so u' = T z with T = I + E, E's only rows the pair nodes' normal ones and its
//! columns the other body's unknowns. No row of E is a column of E (a node is refused as both a
//! first-group and a second-group node), so T⁻¹ = I − E. Matrices are changed by congruence
//! (Tᵀ A T), the load by Tᵀ, states by T and T⁻¹.

use super::dof_map::DofMap;

/// The change of variables u' = T z, T = I + E (module docs), over full indices `node·d + c`:
/// each row of E is a pair node's normal unknown, its entries the other body's unknowns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coupling {
    /// (full row, [(full column, coefficient)]), rows increasing.
    pub rows: Vec<(usize, Vec<(usize, f64)>)>,
}

impl Coupling {
    /// E's rows of the pair nodes `nodes`, each (node i, ν_i, the other body's nodes with
    /// N_k), in the frames `frame_of` (node k's unknowns u'_k = R_kᵀ u_k, `R[row][col]`), `d`
    /// components per node: row (i, 0), columns (k, c) with N_k (R_kᵀ ν_i)_c.
    pub fn new<'a>(
        nodes: impl IntoIterator<Item = (usize, [f64; 3], &'a [(usize, f64)])>,
        frame_of: impl Fn(usize) -> [[f64; 3]; 3],
        d: usize,
    ) -> Self {
        let mut rows = Vec::new();
        for (i, nv, masters) in nodes {
            let mut entries = Vec::new();
            for &(k, nk) in masters {
                let r = frame_of(k);
                let local: [f64; 3] = std::array::from_fn(|c| (0..3).map(|a| r[a][c] * nv[a]).sum());
                for (c, x) in local[..d].iter().enumerate() {
                    if *x != 0.0 {
                        entries.push((k * d + c, nk * x));
                    }
                }
            }
            rows.push((i * d, entries));
        }
        rows.sort_by_key(|r| r.0);
        Coupling { rows }
    }

    /// Tᵀ A T of a matrix given by its triplets (full indices), as triplets: entry (r, c, v)
    /// adds v T_ra T_cb to (a, b), T's column entries of row r being (r, 1) and E's row r.
    pub fn congruence(
        &self,
        n: usize,
        triplets: impl Iterator<Item = (usize, usize, f64)>,
    ) -> Vec<(usize, usize, f64)> {
        let mut row_of = vec![usize::MAX; n];
        for (s, (r, _)) in self.rows.iter().enumerate() {
            row_of[*r] = s;
        }
        let mut out = Vec::new();
        let expand = |r: usize| -> Vec<(usize, f64)> {
            let mut e = vec![(r, 1.0)];
            if row_of[r] != usize::MAX {
                e.extend_from_slice(&self.rows[row_of[r]].1);
            }
            e
        };
        for (r, c, v) in triplets {
            let (er, ec) = (expand(r), expand(c));
            for &(a, ta) in &er {
                for &(b, tb) in &ec {
                    out.push((a, b, ta * v * tb));
                }
            }
        }
        out
    }

    /// The same change of variables on the free unknowns (`dof_of`: full index → free one;
    /// a row's node is never eliminated, an eliminated column is 0 and dropped).
    pub fn on_free(&self, dof_of: &DofMap) -> Self {
        let rows = self
            .rows
            .iter()
            .map(|(r, e)| {
                let r = dof_of.get(*r).expect("a pair's contact node is not clamped");
                (r, e.iter().filter_map(|&(k, x)| dof_of.get(k).map(|k| (k, x))).collect())
            })
            .collect();
        Coupling { rows }
    }

    /// Whether T = I (one body).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// u' = T z in place (full indices).
    pub fn apply(&self, z: &mut [f64]) {
        for (r, e) in &self.rows {
            z[*r] += e.iter().map(|&(k, x)| x * z[k]).sum::<f64>();
        }
    }

    /// z = T⁻¹ u' = (I − E) u' in place (full indices).
    pub fn unapply(&self, u: &mut [f64]) {
        for (r, e) in &self.rows {
            u[*r] -= e.iter().map(|&(k, x)| x * u[k]).sum::<f64>();
        }
    }

    /// f_z = Tᵀ f' in place (full indices).
    pub fn transpose_apply(&self, f: &mut [f64]) {
        for (r, e) in &self.rows {
            let fr = f[*r];
            for &(k, x) in e {
                f[k] += x * fr;
            }
        }
    }
}
