//! The machinery of the registry of the geometries (`__geometries!` in `scene/mod.rs`): what
//! its lines expand to. `define` writes the registry's items into `crate::scene` (the one call,
//! there): [`AnyScene`](super::AnyScene) with one variant per line, the scene aliases,
//! [`RawScene`](super::RawScene) with the line's tables before the shared sections,
//! [`Registered`](super::Registered) for each geometry, and the parser's dispatch over the
//! geometry tables (`AnyScene::parse`); `with_scene` is the match of
//! [`with_scene!`](crate::with_scene). Nothing here names a geometry.

/// Whether two strings are equal, in a constant (a registry line's table against its
/// `SceneGeometry::TABLE`, checked when the crate compiles).
pub(super) const fn same_str(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// What the registry's lines expand to (module docs); called by `__geometries!` only.
#[doc(hidden)]
#[macro_export]
macro_rules! __registry {
    ([with_scene $any:expr, $s:ident => $body:expr] default $default:ident;
     $($(#[$doc:meta])* $V:ident($T:ty) as $A:ident = $t:ident $(+ $x:ident($X:ty))*;)+) => {
        match $any {
            $($crate::scene::AnyScene::$V($s) => $body,)+
        }
    };
    ([define] default $default:ident;
     $($(#[$doc:meta])* $V:ident($T:ty) as $A:ident = $t:ident $(+ $x:ident($X:ty))*;)+) => {
        /// A scene file of any geometry: the geometry table it has decides the variant (a file
        /// without one is a scene of the registry's default table).
        #[derive(Debug, Clone, PartialEq)]
        pub enum AnyScene {
            $($(#[$doc])* $V($crate::spec::Scene<$T>),)+
        }

        $($(#[$doc])* pub type $A = $crate::spec::Scene<$T>;)+

        /// The tables of a scene file (one geometry table at most, with the tables it owns), as
        /// read and as resolved (opaque outside the crate).
        #[derive(Debug, Default, serde::Deserialize, serde::Serialize)]
        #[serde(deny_unknown_fields)]
        pub struct RawScene {
            $(
                #[serde(skip_serializing_if = "Option::is_none")]
                pub(crate) $t: Option<<$T as $crate::spec::SceneGeometry>::Raw>,
                $(
                    #[serde(skip_serializing_if = "Option::is_none")]
                    pub(crate) $x: Option<$X>,
                )*
            )+
            pub(crate) mass: Option<RawMass>,
            pub(crate) scheme: Option<RawScheme>,
            #[serde(skip_serializing_if = "Option::is_none")]
            pub(crate) contact: Option<RawContact>,
            pub(crate) time: Option<RawTime>,
            pub(crate) output: Option<RawOutput>,
        }

        /// The geometry tables in the registry's order, each with its keys that name files
        /// ([`SceneGeometry::FILE_KEYS`]).
        const GEOMETRIES: &[(&str, &[&str])] =
            &[$((<$T as SceneGeometry>::TABLE, <$T as SceneGeometry>::FILE_KEYS)),+];
        /// The table of a scene file that has none.
        const DEFAULT_TABLE: &str = stringify!($default);

        $(
            const _: () = assert!(
                registry::same_str(stringify!($t), <$T as SceneGeometry>::TABLE),
                concat!("the registry line of ", stringify!($V), " names another table than its SceneGeometry::TABLE")
            );

            impl Registered for $T {
                fn from_any(any: AnyScene) -> Result<Scene<Self>, SceneError> {
                    match any {
                        AnyScene::$V(s) => Ok(s),
                        #[allow(unreachable_patterns)]
                        other => Err(wrong_geometry(<Self as SceneGeometry>::TABLE, &other)),
                    }
                }

                #[allow(unused_parens)]
                fn raw_scene(&self) -> RawScene {
                    let (table, ($($x),*)) = SceneGeometry::raw(self);
                    RawScene { $t: Some(table), $($x,)* ..Default::default() }
                }
            }
        )+

        impl AnyScene {
            /// Parses and validates scene text: a table a geometry owns refused without that
            /// geometry's table, one geometry table at most (the default without one), validated
            /// by its geometry ([`SceneGeometry::validate`]) with the tables it owns, then the
            /// sections every scene shares on it.
            #[allow(unused_parens)]
            fn parse(text: &str, inputs: MeshInputs) -> Result<AnyScene, SceneError> {
                let mut raw: RawScene = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
                $($(
                    if raw.$x.is_some() && raw.$t.is_none() {
                        let (owner, why) = (<$T as SceneGeometry>::TABLE, <$T as SceneGeometry>::EXTRAS_WHY);
                        return Err(owned_by(concat!("[", stringify!($x), "]"), owner, why));
                    }
                )*)+
                let present = [$((raw.$t.is_some(), <$T as SceneGeometry>::TABLE)),+];
                one_table(&present)?;
                if present.iter().all(|(has, _)| !has) {
                    raw.$default = Some(Default::default());
                }
                $(
                    if let Some(table) = raw.$t.take() {
                        let geometry = <$T as SceneGeometry>::validate(table, ($(raw.$x.take()),*), inputs)?;
                        return Ok(AnyScene::$V(validated(geometry, raw)?));
                    }
                )+
                unreachable!("a scene without a geometry table has the default one")
            }
        }
    };
}
