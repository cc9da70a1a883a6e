//! The series columns a scene can ask for (`output.series`, one column of `series.csv` each):
//! the vocabulary the observers ([`crate::observe`]), the geometries' own reports
//! ([`crate::problem::GeometryView::own_columns`]) and the scenes share.

/// A per-step diagnostic that can be recorded in `series.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    /// Contact-node displacement u_0ⁿ (plates: the contact node at the lowest y).
    U0,
    /// Displacement of node 1 (bars only).
    U1,
    /// Mean of u on Γ_C (plates).
    UMean,
    /// Contact force λⁿ (plates: the mean pressure Σ_c λ_c / |Γ_C|, the 1D λ for y-independent
    /// fields).
    Lambda,
    /// Total contact force Σ_c λ_c (plates).
    ContactForce,
    /// Discrete energy ½VᵀMV + ½UᵀSU − UᵀF.
    Energy,
    /// Exact ‖u_h(t_n) − u(t_n)‖_{L²(0,L)}.
    L2Error,
    /// Exact u(0, t_n).
    ExactU0,
    /// Exact λ(t_n).
    ExactLambda,
    /// Principal pivots of the step's contact solves (plates).
    Pivots,
    /// A body's nodes in contact, read off the force (`R_i > 0`).
    ActiveNodes,
    /// A body's `min_i d_i` over its contact nodes.
    MinDistance,
    /// A body's momentum component k (0, 1, 2: x, y, z).
    Momentum(u8),
    /// A body's mean displacement component k.
    MeanU(u8),
    /// A solid's `friction_dissipation` so far (Σ over steps and contact nodes of −r_t · Δu_t;
    /// 0 without friction).
    FrictionDissipation,
    /// A solid's contact nodes with normal force that stick / slide (0 without friction).
    StickNodes,
    SlipNodes,
    /// A solid's total tangential reaction Σ_i r_t,i, world component k (0 without friction).
    TangentialForce(u8),
    /// A column of one pair or body of several bodies, named `<name>.<column>`
    /// (`impact.contact_force`, `striker.momentum_x`): its full name (interned, [`intern`]) and
    /// its slot among the geometry's own columns (`crate::solid::report`).
    Dotted {
        name: &'static str,
        slot: u8,
    },
}

/// A `'static` copy of a dotted column's name, made once per distinct name in the process
/// (names come from scenes: a few per scene).
pub fn intern(name: String) -> &'static str {
    static NAMES: std::sync::Mutex<std::collections::BTreeSet<&'static str>> =
        std::sync::Mutex::new(std::collections::BTreeSet::new());
    let mut names = NAMES.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(n) = names.get(name.as_str()) {
        return n;
    }
    let leaked: &'static str = Box::leak(name.into_boxed_str());
    names.insert(leaked);
    leaked
}

impl Column {
    /// The columns of a bar scene.
    pub const BAR: [Column; 7] =
        [Column::U0, Column::U1, Column::Lambda, Column::Energy, Column::L2Error, Column::ExactU0, Column::ExactLambda];
    /// The columns of a plate scene.
    pub const PLATE: [Column; 9] = [
        Column::U0,
        Column::UMean,
        Column::Lambda,
        Column::ContactForce,
        Column::Energy,
        Column::L2Error,
        Column::ExactU0,
        Column::ExactLambda,
        Column::Pivots,
    ];

    /// The columns only a body against an obstacle has.
    pub const BODY: [Column; 8] = [
        Column::ActiveNodes,
        Column::MinDistance,
        Column::Momentum(0),
        Column::Momentum(1),
        Column::Momentum(2),
        Column::MeanU(0),
        Column::MeanU(1),
        Column::MeanU(2),
    ];
    /// The friction columns of every solid (issue 29).
    pub const FRICTION: [Column; 6] = [
        Column::FrictionDissipation,
        Column::StickNodes,
        Column::SlipNodes,
        Column::TangentialForce(0),
        Column::TangentialForce(1),
        Column::TangentialForce(2),
    ];
    /// The columns of a solid scene: a plate's, a body's, then friction's.
    pub const SOLID: [Column; 23] = {
        let mut all = [Column::U0; 23];
        let mut k = 0;
        while k < 23 {
            all[k] = if k < 9 {
                Column::PLATE[k]
            } else if k < 17 {
                Column::BODY[k - 9]
            } else {
                Column::FRICTION[k - 17]
            };
            k += 1;
        }
        all
    };

    /// Whether only a body has this column.
    pub fn is_body(self) -> bool {
        Column::BODY.contains(&self)
    }

    /// The vector component of a body column (None for the others).
    pub fn component(self) -> Option<usize> {
        match self {
            Column::Momentum(k) | Column::MeanU(k) | Column::TangentialForce(k) => Some(k as usize),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Column::U0 => "u0",
            Column::U1 => "u1",
            Column::UMean => "u_mean",
            Column::Lambda => "lambda",
            Column::ContactForce => "contact_force",
            Column::Energy => "energy",
            Column::L2Error => "l2_error",
            Column::ExactU0 => "exact_u0",
            Column::ExactLambda => "exact_lambda",
            Column::Pivots => "pivots",
            Column::ActiveNodes => "active_nodes",
            Column::MinDistance => "min_distance",
            Column::Momentum(k) => ["momentum_x", "momentum_y", "momentum_z"][k.min(2) as usize],
            Column::MeanU(k) => ["mean_u_x", "mean_u_y", "mean_u_z"][k.min(2) as usize],
            Column::FrictionDissipation => "friction_dissipation",
            Column::StickNodes => "stick_nodes",
            Column::SlipNodes => "slip_nodes",
            Column::TangentialForce(k) => {
                ["tangential_force_x", "tangential_force_y", "tangential_force_z"][k.min(2) as usize]
            }
            Column::Dotted { name, .. } => name,
        }
    }

    pub fn needs_exact(self) -> bool {
        matches!(self, Column::L2Error | Column::ExactU0 | Column::ExactLambda)
    }
}
