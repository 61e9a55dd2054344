//! Lowering names: locals, parameters, `f64` constants and the coordinates of the
//! configurations (`q0.x`, `q0.x[i]`, with the adapted coordinates of declared translations).

use syn::{Expr, Member};

use super::{f64_const, Lowering, Value, ACCEPTED};
use crate::front::layout::{Component, Reading};
use crate::ir::graph::Sym;

impl Lowering<'_> {
    pub(super) fn path(&mut self, p: &syn::ExprPath) -> Option<Value> {
        if p.qself.is_none() {
            if let Some(id) = p.path.get_ident() {
                let name = id.to_string();
                if let Some(local) = self.lookup(&name) {
                    return match local.value {
                        Value::Poison => None,
                        ref v => Some(v.clone()),
                    };
                }
                if let Some(i) = self.names.params.iter().position(|q| *q == name) {
                    return Some(Value::Scalar(self.g.var(Sym::Param(i))));
                }
                if id == self.names.q0 || id == self.names.q1 || self.names.dq.contains(id) {
                    let example = self.names.coords.first().map_or("x", |c| c.name.as_str());
                    return self.error(
                        id,
                        format!("use a coordinate of `{id}`, e.g. `{id}.{example}`"),
                    );
                }
                if !self.allow_coords {
                    let list: Vec<String> =
                        self.names.params.iter().map(|p| format!("`{p}`")).collect();
                    return self.error(
                        id,
                        format!(
                            "`{name}` is not a parameter; connection entries are f64 literals or parameters: {}",
                            list.join(", ")
                        ),
                    );
                }
                return self.error(
                    id,
                    format!("cannot find `{name}`: not a local, a parameter or a configuration"),
                );
            }
            let segs: Vec<String> = p
                .path
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect();
            let tail = match segs.as_slice() {
                [f, c, n] if f == "f64" && c == "consts" => Some(n.as_str()),
                [s, f, c, n] if (s == "std" || s == "core") && f == "f64" && c == "consts" => {
                    Some(n.as_str())
                }
                _ => None,
            };
            if let Some(v) = tail.and_then(f64_const) {
                return Some(Value::Scalar(self.g.constant(v)));
            }
        }
        self.error(p, format!("unsupported path; {ACCEPTED}"))
    }

    /// `q0.x` or `q1.x` when `f` reads a coordinate (the configuration names not shadowed by a
    /// local): which configuration (0 or 1), and the member.
    pub(super) fn coordinate_field<'e>(
        &self,
        f: &'e syn::ExprField,
    ) -> Option<(usize, &'e Member)> {
        let Expr::Path(base) = &*f.base else {
            return None;
        };
        let id = base.path.get_ident()?;
        let which = if id == self.names.q0 {
            0
        } else if id == self.names.q1 {
            1
        } else if let Some(d) = self.names.dq.iter().position(|d| d == id) {
            2 + d
        } else {
            return None;
        };
        self.lookup(&id.to_string())
            .is_none()
            .then_some((which, &f.member))
    }

    /// The leaf expression of component `c` of configuration `which`: 0 and 1 the two
    /// configurations, 2 and 3 the virtual displacements of a force.
    pub(super) fn component(&mut self, which: usize, c: Component) -> Value {
        let sym = |i| match which {
            0 => Sym::Q0(i),
            1 => Sym::Q1(i),
            2 => Sym::D0(i),
            _ => Sym::D1(i),
        };
        let n = match c {
            Component::Var(i) => self.g.var(sym(i)),
            Component::Sum(g, r) => {
                let (g, r) = (self.g.var(sym(g)), self.g.var(sym(r)));
                self.g.add(g, r)
            }
        };
        Value::Scalar(n)
    }

    /// Resolves the coordinate named by `member` (reporting an unknown name); the connection
    /// matrix may not read coordinates.
    pub(super) fn coordinate(&self, f: &syn::ExprField, member: &Member) -> Option<usize> {
        if !self.allow_coords {
            self.cx.error_spanned_by(
                f,
                format!(
                    "the connection matrix must be constant: entries are f64 literals and parameters, found the coordinate `{}`",
                    crate::ctxt::show(&f)
                ),
            );
            return None;
        }
        let Member::Named(member) = member else {
            self.cx
                .error_spanned_by(member, "expected a coordinate name");
            return None;
        };
        let name = member.to_string();
        let found = self.names.coords.iter().position(|c| c.name == name);
        if found.is_none() {
            let declared: Vec<String> = self
                .names
                .coords
                .iter()
                .map(|c| match c.len {
                    None => c.name.clone(),
                    Some(n) => format!("{}[{n}]", c.name),
                })
                .collect();
            self.cx.error_spanned_by(
                member,
                format!(
                    "unknown coordinate `{name}`; declared coordinates: {}",
                    declared.join(", ")
                ),
            );
        }
        found
    }

    /// `q0.x[i]`: a component of an array coordinate; the index must be a constant integer.
    pub(super) fn coordinate_index(
        &mut self,
        ix: &syn::ExprIndex,
        f: &syn::ExprField,
        which: usize,
        member: &Member,
    ) -> Option<Value> {
        let c = self.coordinate(f, member);
        let index = self.expr(&ix.index);
        let c = c?;
        let name = self.names.coords[c].name.clone();
        let Some(len) = self.names.coords[c].len else {
            return self.error(
                &ix.index,
                format!(
                    "coordinate `{name}` is a scalar and cannot be indexed: write `{}`; only array coordinates, declared with a length such as `{name}[3]`, are indexed",
                    crate::ctxt::show(&f)
                ),
            );
        };
        let i = match index? {
            Value::Int(i) => i,
            other => {
                return self.error(
                    &ix.index,
                    format!(
                        "the index of coordinate `{name}` must be a constant integer known at compile time, found {} `{}`; accepted: \
                         an integer literal, a loop index of a `for` loop over a constant range, or `+ - * / %` on those, e.g. `{}[(i + 1) % {len}]`",
                        other.kind(),
                        crate::ctxt::show(&ix.index),
                        crate::ctxt::show(&f)
                    ),
                )
            }
        };
        match usize::try_from(i).ok().filter(|&i| i < len) {
            Some(i) => {
                let comp = self.names.coords[c].components[i];
                Some(self.component(which, comp))
            }
            None => self.error(
                &ix.index,
                format!(
                    "index {i} is out of range for coordinate `{name}` of length {len} (valid indices 0..{len}): `{}`",
                    crate::ctxt::show(&ix.index)
                ),
            ),
        }
    }

    /// Whether `member` names a coordinate on a group read whole (a rotation as a matrix, a
    /// direction as a vector, a pose as its parts).
    pub(super) fn is_matrix_coordinate(&self, member: &Member) -> bool {
        let Member::Named(id) = member else {
            return false;
        };
        self.names
            .coords
            .iter()
            .any(|c| *id == c.name && c.matrix.is_some())
    }

    /// The value `reading` reads, its leaves `sym(i)`. A 3 × 3 block of a configuration
    /// (`which`) keeps its origin, so that `q0.R.transpose() * q1.R` reads the relative
    /// rotation ([`super::matrix`]).
    fn read(&mut self, reading: &Reading, sym: fn(usize) -> Sym, which: Option<usize>) -> Value {
        match reading {
            Reading::Entries(1, 1, entries) => Value::Scalar(self.g.var(sym(entries[0]))),
            Reading::Entries(r, cols, entries) => {
                let e = entries.iter().map(|&i| self.g.var(sym(i))).collect();
                let mut m = super::Mat::new(*r, *cols, e);
                if let (Some(which), (3, 3)) = (which, (*r, *cols)) {
                    m.origin = Some((which, entries[0], false));
                }
                Value::Mat(m)
            }
            Reading::Parts(parts) => Value::Parts(
                parts
                    .iter()
                    .map(|(name, part)| (*name, self.read(part, sym, which)))
                    .collect(),
            ),
        }
    }

    pub(super) fn field(&mut self, f: &syn::ExprField) -> Option<Value> {
        if let Some((which, member)) = self.coordinate_field(f) {
            let c = self.coordinate(f, member)?;
            let coord = &self.names.coords[c];
            let sym = match which {
                0 => Sym::Q0,
                1 => Sym::Q1,
                2 => Sym::D0,
                _ => Sym::D1,
            };
            // A force's virtual displacement, the velocity argument of a continuous
            // Lagrangian, or a configuration, on groups.
            let (reading, configuration) = match which {
                2.. if coord.displacement.is_some() => (coord.displacement.as_ref(), false),
                1 if coord.velocity.is_some() => (coord.velocity.as_ref(), false),
                _ => (coord.matrix.as_ref(), true),
            };
            if let Some(reading) = reading.cloned() {
                return Some(self.read(&reading, sym, configuration.then_some(which)));
            }
            if let Some(len) = coord.len {
                let name = coord.name.clone();
                return self.error(
                    f,
                    format!(
                        "`{name}` is an array coordinate of length {len}: read one component at a time, `{}[i]`, with a constant index \
                         (a literal, a loop index, or integer arithmetic on those)",
                        crate::ctxt::show(&f)
                    ),
                );
            }
            let comp = coord.components[0];
            return Some(self.component(which, comp));
        }
        let base = self.expr(&f.base)?;
        match (&f.member, base) {
            (Member::Unnamed(ix), Value::Tuple(items)) => match items.get(ix.index as usize) {
                Some(v) => Some(v.clone()),
                None => self.error(
                    ix,
                    format!(
                        "no field {} on a tuple of {} elements",
                        ix.index,
                        items.len()
                    ),
                ),
            },
            (m, Value::Mat(a)) => self.mat_field(a, m),
            (Member::Named(m), Value::Parts(parts)) => match parts.iter().find(|(n, _)| m == n) {
                Some((_, v)) => Some(v.clone()),
                None => {
                    let names: Vec<String> = parts.iter().map(|(n, _)| format!("`.{n}`")).collect();
                    self.error(m, format!("no part `{m}`; accepted: {}", names.join(", ")))
                }
            },
            (m, v) => self.error(
                m,
                format!("no field `{}` on {}", crate::ctxt::show(&m), v.kind()),
            ),
        }
    }
}
