//! What a geometry's table is to the scene parser ([`SceneGeometry`]): its table as read and as
//! resolved, its validation, and what the shared sections need of it (columns, unknowns,
//! contact weight, what it offers the schemes and laws). Each geometry implements it in its own
//! folder (`bar/table.rs`, `plate/table.rs`, `solid/table/`); the registry of the geometries
//! (`crate::scene`) names each once and reaches them only through this trait.

use super::TimeSpec;
use super::compat::Offer;
use super::error::SceneError;
use crate::mesh_file::MeshInputs;
use crate::observe::Column;

/// What the parser needs of a geometry: its table (read, validated, resolved), its columns, its
/// unknowns and contact weight, and the exact solutions it offers.
pub trait SceneGeometry: Sized {
    /// The geometry's table (`bar`, `plate`, `solid`): its registry line names the same.
    const TABLE: &'static str;
    /// The table as written, read by serde (closed: unknown keys refused, naming the key) and
    /// written back resolved.
    type Raw: serde::Serialize + serde::de::DeserializeOwned + Default + std::fmt::Debug;
    /// The tables the geometry owns beside its own, as read (their registry line names them):
    /// `()` for none, `Option<T>` for one (a solid's `[obstacle]`), a tuple of options for more.
    type Extras;
    /// Why the tables of [`Self::Extras`] belong to this geometry alone: the refusal of one in
    /// another geometry's scene says it (`a [solid] body meets a plane`).
    const EXTRAS_WHY: &'static str = "";
    /// The keys of the table that name a file relative to the scene's folder (`mesh`): inputs
    /// that `run --force` must never delete.
    const FILE_KEYS: &'static [&'static str] = &[];
    /// The columns `output.series` accepts, and their list for messages.
    const COLUMNS: &'static [Column];
    const COLUMN_LIST: &'static str;
    /// The keys that set the number of unknowns (named when the work limit is exceeded).
    const SIZE_KEYS: &'static str;
    /// [`Self::SIZE_KEYS`] of this scene: the keys it has (a mesh file's scene has no `nx`;
    /// issue 32, E16).
    fn size_keys(&self) -> &'static str {
        Self::SIZE_KEYS
    }
    /// Whether the geometry writes VTU frames (`output.vtu`).
    const VTU: bool;
    /// Whether the contact nodes carry unknowns without a contact condition (a solid's
    /// tangential components), massless with them when w_0 = 0: a contact layer ([`Offer`]).
    const MASSLESS_TANGENTS: bool = false;
    /// The table validated (with the tables it owns beside it): every error names its key and
    /// allowed range; a `mesh` key names a file relative to `inputs.base`, or the arrays given
    /// for `"<arrays>"`, read here, once.
    fn validate(raw: Self::Raw, extras: Self::Extras, inputs: MeshInputs) -> Result<Self, SceneError>;
    /// The resolved table (every default filled in) and the tables it owns beside it.
    fn raw(&self) -> (Self::Raw, Self::Extras);
    /// The first line of the resolved file (a comment).
    fn header(&self, time: &TimeSpec) -> String;
    /// Unknowns per step (the work limit's measure).
    fn unknowns(&self) -> usize;
    /// The extent along x (the default `time.end` is 3 L).
    fn length(&self) -> f64;
    /// The mass weights validated on this geometry; returns the largest weight of the cells at
    /// the contact boundary (0 iff the contact unknowns are massless).
    fn contact_weight(&self, mass: &crate::mass::MassKind) -> Result<f64, SceneError>;
    /// What the geometry offers the schemes and laws with this mass (the compatibility rule,
    /// [`super::compat`]). The default: many contact nodes over a sparse back-end, a lumped mass,
    /// the contact weight of [`SceneGeometry::contact_weight`].
    fn offer(&self, mass: &crate::mass::MassKind) -> Result<Offer, SceneError> {
        let w0 = self.contact_weight(mass)?;
        Ok(Offer {
            one_node_system: false,
            // Two bodies with mass at their contact nodes: the pairs' change of variables
            // couples them in the lumped mass (`crate::solid::pair`); massless, it stays diagonal.
            lumped_mass: !(self.pairs() && w0 > 0.0),
            w0,
            contact_layer: Self::MASSLESS_TANGENTS && w0 == 0.0,
            massless_tangents: Self::MASSLESS_TANGENTS && w0 == 0.0,
            one_cell_contact_row: false,
            zero_gap: false,
            tangential_dims: self.tangential_dims(),
            pairs: self.pairs(),
            matrix_free: self.matrix_free(),
            dense_contact: self.dense_contact(),
        })
    }
    /// Whether the geometry has a matrix-free stiffness operator ([`Offer::matrix_free`]).
    fn matrix_free(&self) -> bool {
        false
    }
    /// The contact nodes whose dense Schur complement the rule checks ([`Offer::dense_contact`]).
    fn dense_contact(&self) -> Option<(usize, &'static str)> {
        None
    }
    /// A series column this scene names itself (several bodies' `<pair>.contact_force`), by
    /// its name (None: none of that name).
    fn named_column(&self, _name: &str) -> Option<Column> {
        None
    }
    /// Whether the contact is between bodies (`[[pair]]`s) rather than against an obstacle.
    fn pairs(&self) -> bool {
        false
    }
    /// Each pair's name and its own contact law as written (several bodies' `pair.contact`,
    /// read with `[contact]` by the scene: `crate::scene`'s `pair_law`).
    fn pair_laws(&self) -> Vec<(String, Option<toml::Table>)> {
        Vec::new()
    }
    /// Whether `mass` leaves a node massless that is neither a contact node nor clamped (P2's
    /// edge nodes inside the contact layer): their normal components stay massless under
    /// `mass.contact_directions = "normal"`, a contact layer still ([`Offer::contact_layer`]).
    fn massless_inner_nodes(&self, _mass: &crate::mass::MassKind) -> Result<bool, SceneError> {
        Ok(false)
    }
    /// Tangential directions at a contact node (a solid's d − 1; 0 for bars and plates).
    fn tangential_dims(&self) -> usize {
        0
    }
    /// Why `column` cannot be recorded for this geometry's data (None if it can).
    fn unavailable(&self, column: Column) -> Option<String>;
    /// The series recorded without `output.series`.
    fn default_series(&self) -> Vec<Column>;
    /// An estimate of the memory, in bytes, that setting this geometry up takes before its
    /// first factor (its element-matrix buffers times the measured ratio of the peak to them),
    /// checked against [`crate::linalg::memory_limit`] before any mesh is assembled; each factor
    /// is checked, exactly, after its symbolic analysis, against what is left of the limit
    /// ([`crate::linalg::memory_left`]).
    fn assembly_bytes(&self, scheme: Option<&crate::schemes::SchemeSpec>) -> f64 {
        let _ = scheme;
        0.0
    }
}
