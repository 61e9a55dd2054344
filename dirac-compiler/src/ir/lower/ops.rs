//! Lowering operations: arithmetic, assignment (`=`, `+=`, …), method and function calls, and
//! `for` loops over constant ranges (unrolled).

use std::collections::HashMap;

use syn::{BinOp, Expr, Ident};

use super::{Lowering, Operand, Value, ACCEPTED, MAX_UNROLL, METHODS};
use crate::ir::graph::Fun;

impl Lowering<'_> {
    pub(super) fn binary(&mut self, b: &syn::ExprBinary) -> Option<Value> {
        let compound = match b.op {
            BinOp::AddAssign(_) => Some(BinOp::Add(Default::default())),
            BinOp::SubAssign(_) => Some(BinOp::Sub(Default::default())),
            BinOp::MulAssign(_) => Some(BinOp::Mul(Default::default())),
            BinOp::DivAssign(_) => Some(BinOp::Div(Default::default())),
            _ => None,
        };
        if let Some(op) = compound {
            let l = self.expr(&b.left);
            let r = self.expr(&b.right);
            let (l, r) = (Operand::new(l?, &b.left), Operand::new(r?, &b.right));
            let v = self.arith(op, l, r)?;
            return self.assign(&b.left, v);
        }
        let arithmetic = |op: &BinOp| {
            matches!(
                op,
                BinOp::Add(_) | BinOp::Sub(_) | BinOp::Mul(_) | BinOp::Div(_) | BinOp::Rem(_)
            )
        };
        if !arithmetic(&b.op) {
            return self.error(b.op, format!("unsupported operator; {ACCEPTED}"));
        }
        // A chain `a + b + c + ..` is a tree as deep as it is long, nested in its left operands:
        // it is walked down its left spine with a loop, and folded from the innermost operation
        // outwards, so a sum of 10⁵ terms needs no stack per term. Every operand is lowered, and
        // every operation applied, in the order of the recursion `l = expr(left); r =
        // expr(right); arith(l, r)` (the graph, and so the code, is the same).
        let mut spine = vec![b];
        let mut leftmost = &*b.left;
        while let Expr::Binary(inner) = leftmost {
            if !arithmetic(&inner.op) {
                break;
            }
            spine.push(inner);
            leftmost = &inner.left;
        }
        let mut value = self.expr(leftmost);
        for node in spine.into_iter().rev() {
            let r = self.expr(&node.right);
            value = match (value, r) {
                (Some(l), Some(r)) => {
                    let (l, r) = (Operand::new(l, &node.left), Operand::new(r, &node.right));
                    self.arith(node.op, l, r)
                }
                _ => None,
            };
        }
        value
    }

    pub(super) fn arith(&mut self, op: BinOp, l: Operand, r: Operand) -> Option<Value> {
        if let (Value::Int(a), Value::Int(c)) = (&l.value, &r.value) {
            let v = match op {
                BinOp::Add(_) => a.checked_add(*c),
                BinOp::Sub(_) => a.checked_sub(*c),
                BinOp::Mul(_) => a.checked_mul(*c),
                // Integer `/` and `%` as in Rust (truncating), for index arithmetic such
                // as `(i + 1) % n`.
                BinOp::Div(_) | BinOp::Rem(_) if *c == 0 => {
                    return self.error(op, "integer division by zero")
                }
                BinOp::Div(_) => a.checked_div(*c),
                BinOp::Rem(_) => a.checked_rem(*c),
                _ => unreachable!("arith is called with + - * / % only"),
            };
            return match v {
                Some(v) => Some(Value::Int(v)),
                None => self.error(op, "integer overflow"),
            };
        }
        if matches!(l.value, Value::Mat(_)) || matches!(r.value, Value::Mat(_)) {
            return self.mat_arith(op, l, r);
        }
        if let BinOp::Rem(_) = op {
            return self.error(
                op,
                "`%` is accepted on constant integers only (index arithmetic such as `(i + 1) % n`), not on f64 values",
            );
        }
        let a = self.scalar(l.value, l.at);
        let c = self.scalar(r.value, r.at);
        let (a, c) = (a?, c?);
        let n = match op {
            BinOp::Add(_) => self.g.add(a, c),
            BinOp::Sub(_) => self.g.sub(a, c),
            BinOp::Mul(_) => self.g.mul(a, c),
            BinOp::Div(_) => self.g.div(a, c),
            _ => unreachable!("arith is called with + - * / on f64 only"),
        };
        Some(Value::Scalar(n))
    }

    pub(super) fn assign(&mut self, target: &Expr, value: Value) -> Option<Value> {
        match target {
            Expr::Path(p) if p.path.get_ident().is_some() => {
                let id = p.path.get_ident().expect("checked");
                let name = id.to_string();
                let Some(scope) = self.scopes.iter_mut().rev().find(|s| s.contains_key(&name))
                else {
                    if self.names.params.contains(&name) {
                        return self.error(
                            id,
                            format!(
                                "cannot assign to parameter `{name}`: bind a local with `let mut`"
                            ),
                        );
                    }
                    return self.error(
                        id,
                        format!("cannot assign to `{name}`: not a local variable"),
                    );
                };
                let local = scope.get_mut(&name).expect("found");
                if !local.mutable {
                    return self.error(id, format!("cannot assign twice to immutable variable `{name}`: declare it with `let mut {name}`"));
                }
                local.value = value;
                Some(Value::Unit)
            }
            Expr::Index(ix) if matches!(&*ix.expr, Expr::Field(f) if self.coordinate_field(f).is_some()) => {
                self.error(
                    target,
                    "coordinates are inputs and cannot be assigned: bind a local with `let mut`",
                )
            }
            Expr::Index(ix) => {
                let i = self.expr(&ix.index)?;
                let i = self.int(i, &ix.index)?;
                let Expr::Path(p) = &*ix.expr else {
                    return self.error(&ix.expr, "only elements of local arrays can be assigned");
                };
                let Some(id) = p.path.get_ident() else {
                    return self.error(p, "only elements of local arrays can be assigned");
                };
                let name = id.to_string();
                let Some(local) = self.scopes.iter_mut().rev().find_map(|s| s.get_mut(&name))
                else {
                    return self.error(
                        id,
                        format!("cannot assign to `{name}`: not a local variable"),
                    );
                };
                if !local.mutable {
                    return self.error(id, format!("cannot assign to an element of immutable array `{name}`: declare it with `let mut {name}`"));
                }
                let Value::Array(items) = &mut local.value else {
                    return self.error(id, format!("`{name}` is not an array"));
                };
                let len = items.len();
                match usize::try_from(i).ok().and_then(|i| items.get_mut(i)) {
                    Some(slot) => *slot = value,
                    None => {
                        return self.error(
                            &ix.index,
                            format!("index {i} is out of bounds for an array of length {len}"),
                        )
                    }
                }
                Some(Value::Unit)
            }
            Expr::Field(f) if matches!(&*f.base, Expr::Path(p) if p.path.get_ident().is_some_and(|id| id == self.names.q0 || id == self.names.q1)) => {
                self.error(
                    target,
                    "coordinates are inputs and cannot be assigned: bind a local with `let mut`",
                )
            }
            other => self.error(
                other,
                "only local variables and elements of local arrays can be assigned",
            ),
        }
    }

    pub(super) fn call(
        &mut self,
        method: &Ident,
        receiver: Value,
        receiver_expr: &Expr,
        args: &[&Expr],
    ) -> Option<Value> {
        if let Value::Mat(m) = receiver {
            return self.mat_method(method, m, args);
        }
        let name = method.to_string();
        let arity = match name.as_str() {
            "powi" | "powf" | "atan2" => 1,
            n if Fun::from_name(n).is_some() => 0,
            _ => {
                return self.error(
                    method,
                    format!("unsupported method `{name}`; accepted f64 methods: {METHODS}"),
                );
            }
        };
        if args.len() != arity {
            return self.error(
                method,
                format!("`{name}` takes {arity} argument(s), found {}", args.len()),
            );
        }
        if !matches!(receiver, Value::Scalar(_)) {
            return self.error(
                receiver_expr,
                format!("`.{name}()` needs an f64, found {}", receiver.kind()),
            );
        }
        let x = self.scalar(receiver, receiver_expr)?;
        if name == "powi" {
            let e = self.expr(args[0])?;
            let n = self.int(e, args[0])?;
            let Ok(n) = i32::try_from(n) else {
                return self.error(args[0], "the `powi` exponent must fit in an i32");
            };
            return Some(Value::Scalar(self.g.powi(x, n)));
        }
        if name == "powf" || name == "atan2" {
            let e = self.expr(args[0])?;
            let y = self.scalar(e, args[0])?;
            let n = if name == "powf" {
                self.g.powf(x, y)
            } else {
                self.g.atan2(x, y)
            };
            return Some(Value::Scalar(n));
        }
        let f = Fun::from_name(&name).expect("checked above");
        Some(Value::Scalar(self.g.fun(f, x)))
    }

    pub(super) fn for_loop(&mut self, f: &syn::ExprForLoop) -> Option<Value> {
        if let Some(label) = &f.label {
            return self.error(label, "loop labels are not supported");
        }
        let Expr::Range(range) = &*f.expr else {
            return self.error(
                &f.expr,
                "`for` loops must run over a constant range such as `0..3` or `0..=2`",
            );
        };
        let bound = |s: &mut Self, e: &Option<Box<Expr>>| -> Option<i64> {
            let Some(e) = e else {
                s.error(range, "the range must have both bounds, e.g. `0..3`");
                return None;
            };
            match s.expr(e) {
                Some(Value::Int(i)) => Some(i),
                Some(v) => {
                    s.error(
                        e,
                        format!(
                            "loop bounds must be constant integers (literals or enclosing loop indices) so the loop can be unrolled, found {} `{}`",
                            v.kind(),
                            crate::ctxt::show(&e)
                        ),
                    );
                    None
                }
                None => None,
            }
        };
        let start = bound(self, &range.start);
        let end = bound(self, &range.end);
        let (start, mut end) = (start?, end?);
        if matches!(range.limits, syn::RangeLimits::Closed(_)) {
            end += 1;
        }
        if end - start > MAX_UNROLL {
            return self.error(
                range,
                format!("loops are unrolled at compile time: at most {MAX_UNROLL} iterations"),
            );
        }
        for i in start..end {
            self.scopes.push(HashMap::new());
            let bound = self.bind(&f.pat, Value::Int(i));
            let body = bound.and_then(|_| self.block(&f.body));
            self.scopes.pop();
            body?;
        }
        Some(Value::Unit)
    }
}
