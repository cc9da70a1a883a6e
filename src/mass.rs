//! Mass redistribution: one weight per element (paper §3, `w_h = Σ_j w_j χ_j`).
//!
//! Element j is `[jh, (j+1)h]`. The contact node x = 0 only belongs to element 0, so `w_0 = 0`
//! removes its inertia; the mass of element 0 (h) is then redistributed:
//! - (Mod 1) nowhere: `w_1 = … = w_{m-1} = 1`, total mass `L − h`;
//! - (Mod 2) uniformly: `w_1 = … = w_{m-1} = m/(m−1)`, total mass `L`;
//! - (Mod 3) to the nearest neighbour: `w_1 = 2`, `w_2 = … = 1`, total mass `L`.
//!
//! `standard` (all weights 1) is the classical, unmodified mass matrix.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Which redistribution of the contact node's mass to use: the `[mass]` table of a scene, tagged
/// by `kind` (`weights` only for `custom`), through [`MassTable`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(into = "MassTable", from = "MassTable")]
pub enum MassKind {
    Standard,
    Mod1,
    Mod2,
    Mod3,
    /// One weight per element, element 0 first.
    Custom(Vec<f64>),
}

/// The serde form of [`MassKind`]: an internally tagged enum (`Custom` as a struct variant, which
/// internal tagging needs; its weights are checked on the mesh, [`MassKind::weights`]). serde
/// spells the variants as [`MassKind::name`] does (lowercase; checked by a test).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
enum MassTable {
    Standard,
    Mod1,
    Mod2,
    Mod3,
    Custom { weights: Vec<f64> },
}

impl From<MassTable> for MassKind {
    fn from(t: MassTable) -> Self {
        match t {
            MassTable::Standard => MassKind::Standard,
            MassTable::Mod1 => MassKind::Mod1,
            MassTable::Mod2 => MassKind::Mod2,
            MassTable::Mod3 => MassKind::Mod3,
            MassTable::Custom { weights } => MassKind::Custom(weights),
        }
    }
}

impl From<MassKind> for MassTable {
    fn from(m: MassKind) -> Self {
        match m {
            MassKind::Standard => MassTable::Standard,
            MassKind::Mod1 => MassTable::Mod1,
            MassKind::Mod2 => MassTable::Mod2,
            MassKind::Mod3 => MassTable::Mod3,
            MassKind::Custom(weights) => MassTable::Custom { weights },
        }
    }
}

/// Which components of the contact layer's nodes lose their mass (`mass.contact_directions`,
/// issue 29): `All`, every component (the layers as the paper writes them for bars and plates,
/// and today's solids); `Normal`, only the component along the obstacle's normal, the
/// tangential components keeping the standard mass. With friction the tangential components of
/// a massless contact node are quasi-static and the semi-discrete problem loses its
/// well-posedness; removing the mass in the normal direction only restores it (Ligurský and
/// Renard, "A well-posed semi-discretization of elastodynamic contact problems with friction",
/// Q. J. Mech. Appl. Math. 64 (2011) 215–238).
///
/// A solid's mass is then `M = M_std ⊗ (I − n nᵀ) + M_w ⊗ n nᵀ`, which in the obstacle's frame
/// (first axis n) weights component 0 with the layers and the others with 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactDirections {
    #[default]
    All,
    Normal,
}

impl ContactDirections {
    /// The scene name (`mass.contact_directions`).
    pub fn name(self) -> &'static str {
        match self {
            ContactDirections::All => "all",
            ContactDirections::Normal => "normal",
        }
    }

    /// The weight of vector component `component` (0: the normal one, in the obstacle's frame)
    /// in a cell of layer weight `w`.
    pub fn weight(self, component: usize, w: f64) -> f64 {
        match self {
            ContactDirections::Normal if component > 0 => 1.0,
            _ => w,
        }
    }
}

/// Invalid element weights.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MassError {
    #[error(
        "mass.weights has {given} entries but the bar has {elements} elements (one weight per element, element 0 at the contact node)"
    )]
    WrongCount { given: usize, elements: usize },
    #[error("mass.weights[{element}] = {value}: weights must be finite and >= 0")]
    InvalidWeight { element: usize, value: f64 },
    #[error(
        "mass.weights[{left}] = mass.weights[{right}] = 0 make node {node} massless: the reduced mass matrix M* is singular (only the contact node, via element 0, may lose its mass)"
    )]
    MasslessNode { node: usize, left: usize, right: usize },
    #[error("mass.kind = \"{kind}\" needs at least {min} elements, the bar has {elements}")]
    TooFewElements { kind: &'static str, min: usize, elements: usize },
}

impl MassKind {
    /// One mass of every kind (custom without weights), in the order messages list them.
    pub fn all() -> [MassKind; 5] {
        [MassKind::Standard, MassKind::Mod1, MassKind::Mod2, MassKind::Mod3, MassKind::Custom(Vec::new())]
    }

    /// The scene name (`mass.kind`): the one list of mass names.
    pub fn name(&self) -> &'static str {
        match self {
            MassKind::Standard => "standard",
            MassKind::Mod1 => "mod1",
            MassKind::Mod2 => "mod2",
            MassKind::Mod3 => "mod3",
            MassKind::Custom(_) => "custom",
        }
    }

    /// The m element weights, validated (see [`validate_weights`]).
    pub fn weights(&self, m: usize) -> Result<Vec<f64>, MassError> {
        if m < 2 {
            return Err(MassError::TooFewElements { kind: self.name(), min: 2, elements: m });
        }
        let w = match self {
            MassKind::Standard => vec![1.0; m],
            MassKind::Mod1 => massless_contact(m, |_| 1.0),
            MassKind::Mod2 => massless_contact(m, |_| m as f64 / (m as f64 - 1.0)),
            MassKind::Mod3 => massless_contact(m, |j| if j == 1 { 2.0 } else { 1.0 }),
            MassKind::Custom(w) => w.clone(),
        };
        validate_weights(&w, m)?;
        Ok(w)
    }
}

fn massless_contact(m: usize, w: impl Fn(usize) -> f64) -> Vec<f64> {
    (0..m).map(|j| if j == 0 { 0.0 } else { w(j) }).collect()
}

/// Checks count, finiteness and sign, and that no node other than the contact node is massless:
/// node i (1 ≤ i ≤ m−1) lies in elements i−1 and i, so `M*_ii = h/3 (w_{i−1} + w_i)` vanishes
/// (and M* is singular) exactly when both are zero.
pub fn validate_weights(w: &[f64], m: usize) -> Result<(), MassError> {
    if w.len() != m {
        return Err(MassError::WrongCount { given: w.len(), elements: m });
    }
    if let Some((element, &value)) = w.iter().enumerate().find(|(_, v)| !(v.is_finite() && **v >= 0.0)) {
        return Err(MassError::InvalidWeight { element, value });
    }
    if let Some(i) = (1..m).find(|&i| w[i - 1] == 0.0 && w[i] == 0.0) {
        return Err(MassError::MasslessNode { node: i, left: i - 1, right: i });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_masses_follow_the_paper() {
        let m = 6;
        assert_eq!(MassKind::Mod1.weights(m).unwrap(), vec![0.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        assert_eq!(MassKind::Mod3.weights(m).unwrap(), vec![0.0, 2.0, 1.0, 1.0, 1.0, 1.0]);
        let w2 = MassKind::Mod2.weights(m).unwrap();
        assert_eq!(w2[0], 0.0);
        assert!(w2[1..].iter().all(|&w| w == 6.0 / 5.0));
    }

    /// serde's spelling of every kind is [`MassKind::name`]; the table round-trips. (Mutation:
    /// `#[serde(rename = "mod02")]` on `MassTable::Mod2` -> fails at its kind.)
    #[test]
    fn serde_names_are_the_written_names() {
        for kind in MassKind::all() {
            let table = toml::Table::try_from(&kind).unwrap();
            assert_eq!(table["kind"].as_str(), Some(kind.name()));
            assert_eq!(table.contains_key("weights"), matches!(kind, MassKind::Custom(_)), "{}", kind.name());
            assert_eq!(table.clone().try_into::<MassKind>().unwrap(), kind);
        }
        let m: MassKind = toml::from_str("kind = \"custom\"\nweights = [0, 2.5]").unwrap();
        assert_eq!(m, MassKind::Custom(vec![0.0, 2.5]));
    }

    #[test]
    fn bad_weights_name_the_element() {
        assert_eq!(validate_weights(&[1.0, 1.0], 3), Err(MassError::WrongCount { given: 2, elements: 3 }));
        assert!(matches!(validate_weights(&[0.0, -1.0, 1.0], 3), Err(MassError::InvalidWeight { element: 1, .. })));
        assert!(matches!(validate_weights(&[0.0, 1.0, f64::NAN], 3), Err(MassError::InvalidWeight { element: 2, .. })));
        assert_eq!(
            validate_weights(&[1.0, 0.0, 0.0, 1.0], 4),
            Err(MassError::MasslessNode { node: 2, left: 1, right: 2 })
        );
        assert_eq!(validate_weights(&[0.0, 0.0, 1.0], 3), Err(MassError::MasslessNode { node: 1, left: 0, right: 1 }));
    }
}
