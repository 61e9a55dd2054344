//! The coordinate layout: the user's coordinates (scalars and arrays) and the configuration
//! vector `q = (x, g)` the system works in, related by the adapted coordinates of declared
//! translations (§2.2.1).

use crate::ctxt::Ctxt;
use syn::Ident;

/// Largest accepted length of an array coordinate (the configuration vector is a fixed-size
/// nalgebra vector, and every component is a leaf of the expression graph).
pub const MAX_COMPONENTS: usize = 4096;

/// A declared coordinate: a scalar (`len = None`) or an array of `len` components.
#[derive(Clone)]
pub struct Coord {
    pub name: Ident,
    pub len: Option<usize>,
}

impl Coord {
    /// The names of its components: `x`, or `x[0]`, `x[1]`, ….
    pub fn component_names(&self) -> Vec<String> {
        match self.len {
            None => vec![self.name.to_string()],
            Some(n) => (0..n).map(|i| format!("{}[{i}]", self.name)).collect(),
        }
    }

    /// `x` or `x[3]`, as declared.
    pub fn declared(&self) -> String {
        match self.len {
            None => self.name.to_string(),
            Some(n) => format!("{}[{n}]", self.name),
        }
    }
}

/// What one group dimension is, for messages: a declared group coordinate (component), or a
/// `translate(...)` key.
pub enum GroupDecl {
    /// `group(theta)` or a component of `group(c[3])`: the name of the component (`c[1]`).
    Coordinate { ident: Ident, component: String },
    /// `translate(a, b, ...)`: the key and the coordinates it moves together.
    Translate { key: Ident, names: Vec<Ident> },
}

/// The coordinates: the user's (the fields of `<Name>Config`, flattened in order into the user
/// configuration vector) and the configuration vector the system works in, `q = (x, g)` with
/// `S` shape and `K` group coordinates (the trivialization `Q = Σ × G` of §2.2.1).
///
/// With `shape(...), group(...)` the two vectors are the same. With `coordinates(...)` and
/// `translate(...)` keys they are related by a unimodular `q_user = T q`: for the `j`-th
/// `translate(a, b, ...)`, the group coordinate `g_j` is the first component `a[0]` of the
/// first listed coordinate, and every other component `c` of the listed coordinates becomes the
/// shape coordinate `r_c = c − a[0]`, so `a[0] = g_j`, `c = g_j + r_c`; coordinates in no
/// `translate` stay shape coordinates unchanged. The shape coordinates follow the order of the
/// user's flattened components (skipping the group components), then the `K` group coordinates
/// follow in the order of the `translate` keys. Translating `g_j` moves every listed component
/// together: the declared symmetry, now a translation of a group coordinate with `B = 0`.
pub struct Layout {
    /// The user's coordinates, in the order of `<Name>Config`'s fields.
    pub coords: Vec<Coord>,
    /// Names of the `S` shape coordinates (`x`, `x[3]`, `x[3] - x[0]`).
    pub shape: Vec<String>,
    /// Names of the `K` group coordinates.
    pub group: Vec<String>,
    /// One per group coordinate.
    pub group_decls: Vec<GroupDecl>,
    /// One per component of the user configuration vector: its expression in `q`.
    pub components: Vec<Component>,
    /// Whether the symmetry is declared on the user's coordinates (`translate`): then
    /// `q_user ≠ q` in general and the emitted code converts.
    pub declared: bool,
}

impl Layout {
    /// `shape(...), group(...)`: the user's vector is the configuration vector.
    pub fn explicit(shape: Vec<Coord>, group: Vec<Coord>) -> Layout {
        let names =
            |cs: &[Coord]| -> Vec<String> { cs.iter().flat_map(Coord::component_names).collect() };
        let (shape_names, group_names) = (names(&shape), names(&group));
        let group_decls = group
            .iter()
            .flat_map(|c| {
                c.component_names()
                    .into_iter()
                    .map(|component| GroupDecl::Coordinate {
                        ident: c.name.clone(),
                        component,
                    })
            })
            .collect();
        let n = shape_names.len() + group_names.len();
        Layout {
            coords: shape.into_iter().chain(group).collect(),
            shape: shape_names,
            group: group_names,
            group_decls,
            components: (0..n).map(Component::Var).collect(),
            declared: false,
        }
    }

    /// `coordinates(...), translate(...), ...`: adapted coordinates (see [`Layout`]).
    pub fn declared(cx: &Ctxt, coords: Vec<Coord>, translates: &[(Ident, Vec<Ident>)]) -> Layout {
        // Which translate each coordinate belongs to.
        let mut owner: Vec<Option<usize>> = vec![None; coords.len()];
        let mut decls = Vec::new();
        for (key, names) in translates {
            let j = decls.len();
            let mut valid = Vec::new();
            for name in names {
                match coords.iter().position(|c| c.name == *name) {
                    None => cx.error_spanned_by(
                        name,
                        format!(
                            "unknown coordinate `{name}` in `translate(...)`; declared coordinates: {}",
                            coords.iter().map(|c| format!("`{}`", c.name)).collect::<Vec<_>>().join(", ")
                        ),
                    ),
                    Some(i) if owner[i].is_some() => cx.error_spanned_by(
                        name,
                        format!(
                            "coordinate `{name}` is already translated by an earlier `translate(...)`: a coordinate may appear in at most one translation"
                        ),
                    ),
                    Some(i) => {
                        owner[i] = Some(j);
                        valid.push(i);
                    }
                }
            }
            if let Some(&first) = valid.first() {
                decls.push((key.clone(), names.clone(), first));
            }
        }
        let k = decls.len();
        // The flattened user components: (coordinate, name).
        let flat: Vec<(usize, String)> = coords
            .iter()
            .enumerate()
            .flat_map(|(i, c)| c.component_names().into_iter().map(move |n| (i, n)))
            .collect();
        let first_component = |i: usize| {
            flat.iter()
                .position(|(c, _)| *c == i)
                .expect("a coordinate has a component")
        };
        let group_components: Vec<usize> = decls
            .iter()
            .map(|&(_, _, first)| first_component(first))
            .collect();
        let group: Vec<String> = group_components
            .iter()
            .map(|&u| flat[u].1.clone())
            .collect();
        let s = flat.len() - k;
        let mut shape = Vec::with_capacity(s);
        let mut components = Vec::with_capacity(flat.len());
        for (u, (c, name)) in flat.iter().enumerate() {
            if let Some(j) = group_components.iter().position(|&g| g == u) {
                components.push(Component::Var(s + j));
                continue;
            }
            let index = shape.len();
            match owner[*c] {
                Some(j) => {
                    shape.push(format!("{name} - {}", group[j]));
                    components.push(Component::Sum(s + j, index));
                }
                None => {
                    shape.push(name.clone());
                    components.push(Component::Var(index));
                }
            }
        }
        Layout {
            coords,
            shape,
            group,
            group_decls: decls
                .into_iter()
                .map(|(key, names, _)| GroupDecl::Translate { key, names })
                .collect(),
            components,
            declared: true,
        }
    }

    /// Whether some coordinate is an array.
    pub fn has_arrays(&self) -> bool {
        self.coords.iter().any(|c| c.len.is_some())
    }

    /// Number of shape coordinates `S`.
    pub fn s(&self) -> usize {
        self.shape.len()
    }

    /// Number of group coordinates `K`.
    pub fn k(&self) -> usize {
        self.group.len()
    }

    /// Names of the user's components, in the order of the user configuration vector.
    pub fn user_components(&self) -> Vec<String> {
        self.coords
            .iter()
            .flat_map(Coord::component_names)
            .collect()
    }

    /// The coordinates the body reads, and how each component is formed from `q`.
    pub fn lowering_coords(&self) -> Vec<CoordName> {
        let mut at = 0;
        self.coords
            .iter()
            .map(|c| {
                let n = c.len.unwrap_or(1);
                let comps = self.components[at..at + n].to_vec();
                at += n;
                CoordName {
                    name: c.name.to_string(),
                    len: c.len,
                    components: comps,
                    matrix: None,
                    velocity: None,
                    displacement: None,
                }
            })
            .collect()
    }

    /// `q = T⁻¹ q_user`, evaluated (for the invariance check's sample points).
    pub fn to_adapted(&self, user: &[f64]) -> Vec<f64> {
        let mut q = vec![0.0; user.len()];
        for (u, c) in self.components.iter().enumerate() {
            if let Component::Var(a) = *c {
                q[a] = user[u];
            }
        }
        for (u, c) in self.components.iter().enumerate() {
            if let Component::Sum(g, r) = *c {
                q[r] = user[u] - q[g];
            }
        }
        q
    }
}

/// How one component of a user coordinate is formed from the configuration vector `q`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Component {
    /// `q[i]`.
    Var(usize),
    /// `q[g] + q[r]`: a component `c = g + r_c` of a coordinate moved by a declared translation,
    /// with `g` its group coordinate and `r_c = c − g` its shape coordinate (§2.2.1).
    Sum(usize, usize),
}

/// A coordinate the body reads as `q0.name` (a scalar), `q0.name[i]` (an array), or as a
/// matrix or vector value (a coordinate on a group, [`crate::front::lie`]).
pub struct CoordName {
    pub name: String,
    /// `None` for a scalar, the length for an array.
    pub len: Option<usize>,
    /// One per component.
    pub components: Vec<Component>,
    /// A coordinate on a group read whole (a rotation as a 3 × 3 matrix, a direction as a
    /// 3 × 1 vector, a pose as its `rotation` and `translation`): the entries of the stored
    /// point it reads.
    pub matrix: Option<Reading>,
    /// What the velocity argument of a continuous Lagrangian on groups reads for this
    /// coordinate (a scalar's rate, a rotation's body angular velocity, ...), in velocity
    /// symbols.
    pub velocity: Option<Reading>,
    /// What a force's virtual displacement reads for this coordinate on groups (a rotation's
    /// `η` with `δR = R η̂`, a direction's tangent vector `δn`, a scalar's `δx`, ...), in
    /// displacement symbols.
    pub displacement: Option<Reading>,
}

/// How the body reads a coordinate on a group, or its velocity or virtual displacement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reading {
    /// A `rows × cols` matrix (`1 × 1`: an f64) of these symbol indices, row by row.
    Entries(usize, usize, Vec<usize>),
    /// A value with named parts, each read on its own (a pose's `rotation` and `translation`).
    Parts(Vec<(&'static str, Reading)>),
}

impl Reading {
    /// A `rows × cols` matrix of the consecutive symbols from `at`.
    pub fn block(rows: usize, cols: usize, at: usize) -> Reading {
        Reading::Entries(rows, cols, (at..at + rows * cols).collect())
    }
}

impl CoordName {
    /// Scalar coordinates `q[0]`, `q[1]`, … named `names`, in order.
    pub fn scalars(names: impl IntoIterator<Item = String>) -> Vec<CoordName> {
        names
            .into_iter()
            .enumerate()
            .map(|(i, name)| CoordName {
                name,
                len: None,
                components: vec![Component::Var(i)],
                matrix: None,
                velocity: None,
                displacement: None,
            })
            .collect()
    }
}
