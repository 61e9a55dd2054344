//! How deep a text's syntax can make the compiler recurse, measured before it is parsed, so
//! that a text either compiles or is refused with an error naming the limit — never a stack
//! overflow, which would abort the program (a Python session, a command line) that compiles it.
//!
//! `syn`'s parser, the trees it builds (dropped, cloned and printed by derived code) and the
//! lowering recurse once per level of nesting. Levels come from groups (`(..)`, `[..]`, `{..}`),
//! from prefixes (`- - x`, `!x`, `return`, closures, `else if` chains), which `syn` parses
//! recursively, and from chains of binary and postfix operators (`a + b + c`, `x.sin().cos()`),
//! which it parses in a loop into a tree as deep as the chain. The scan here walks the tokens
//! with an explicit stack (as `proc_macro2` tokenizes and drops them) and bounds each kind:
//!
//! * groups nested deeper than [`MAX_NESTING`] and runs of prefixes longer than [`MAX_NESTING`]
//!   are refused at the token that passes the limit;
//! * every other token that can add a level counts, summed over the enclosing groups: a binary
//!   operator one level for the rest of its statement (`syn` parses a chain in a loop, and the
//!   lowering folds it in a loop, so a level of a chain costs only the syntax tree's drop); a
//!   keyword, a closure's `|` or a generic argument's `<` [`PREFIX_LEVELS`] for the rest of the
//!   statement; a unary operator, a `.` (a field or a method call) or a call's or an index's
//!   arguments [`PREFIX_LEVELS`] for the rest of its operand (the lowering recurses into them);
//!   the contents of a group [`GROUP_LEVELS`] more than the group. The deepest token's levels `D`
//!   bound every recursion. The compilation then runs on a stack of [`MIN_STACK`] + `D` ×
//!   [`BYTES_PER_LEVEL`] bytes (a fresh segment when the current one is smaller, as
//!   `crate::stack` does for the attribute), and a text with `D` above [`MAX_LEVELS`] is
//!   refused.
//!
//! The graph stages after the lowering (differentiation, simplification, the programs) walk the
//! expression graph with explicit stacks, so a long chain of `let` statements (a graph as deep as
//! the chain) needs no stack beyond this bound.

use proc_macro2::{Delimiter, Spacing, Span, TokenStream, TokenTree};

/// The most groups nested in one another, the longest run of prefixes (unary operators,
/// `return`, closures) and the most generic arguments nested in one another: far beyond what any
/// Lagrangian, hand-written or generated, needs.
pub const MAX_NESTING: usize = 256;

/// The most levels a text may have (operators and groups along a statement, summed over the
/// enclosing groups): a flat sum of several 10⁶ terms.
pub const MAX_LEVELS: usize = 8_000_000;

/// The stack a level may use, for `syn`'s parser, its trees' derived code and the lowering: 512
/// bytes in an optimized build (a frame of the lowering's recursion is 1.6 KiB there, and gets
/// [`PREFIX_LEVELS`] levels), 4 KiB with debug assertions (unoptimized frames are several times
/// larger). Checked in release builds (dirac-jit's `tests/large_texts.rs`) on 10⁵-deep chains of
/// each kind the scan lets through (flat sums of 2.2 × 10⁵ terms and of 3 × 10⁵ single names,
/// method calls, closures, `else if`) and on groups nested 250 deep. The reservation is address
/// space only: pages are committed when touched.
const BYTES_PER_LEVEL: usize = if cfg!(debug_assertions) { 4096 } else { 512 };

/// The levels of a group's contents above its own: parsing a nested group goes through the
/// whole chain of `syn`'s expression parsers.
const GROUP_LEVELS: usize = 64;

/// The levels of a prefix (a unary operator, a keyword such as `return` or `else`, a closure's
/// `|`, a generic argument's `<`): `syn` parses what follows it by recursing.
const PREFIX_LEVELS: usize = 8;

/// What every compilation of a text gets at least.
pub const MIN_STACK: usize = 16 * 1024 * 1024;

/// Keywords that `syn` parses by recursing into what follows, or that continue an expression
/// across what would otherwise end it (`else if` chains).
const PREFIX_KEYWORDS: &[&str] = &[
    "return", "break", "yield", "move", "async", "static", "let", "else", "if", "box", "dyn",
    "impl", "mut", "ref", "const", "unsafe", "as", "in", "for", "while", "loop", "match",
];

/// Why a text is refused before parsing: the message and where it points.
pub struct TooDeep {
    /// The token that passes the limit.
    pub span: Span,
    /// What the limit is and how to stay within it.
    pub message: String,
}

/// The stack the compilation of `tokens` needs, or why it is refused (see the module
/// documentation for how a token's levels are counted; a statement ends at `;`, or at `,`
/// outside generic arguments).
pub fn stack_for(tokens: TokenStream) -> Result<usize, TooDeep> {
    // One frame per open group: its tokens, the levels up to it, and the state of its current
    // statement.
    struct Frame {
        tokens: proc_macro2::token_stream::IntoIter,
        base: usize,
        spine: usize,
        operand: usize,
        run: usize,
        angles: usize,
        after_operand: bool,
        joint: Option<char>,
    }
    let frame = |tokens: TokenStream, base: usize| Frame {
        tokens: tokens.into_iter(),
        base,
        spine: 0,
        operand: 0,
        run: 0,
        angles: 0,
        after_operand: false,
        joint: None,
    };
    let refuse = |span: Span, message: String| Err(TooDeep { span, message });
    let mut stack = vec![frame(tokens, 0)];
    let (mut deepest, mut deepest_at) = (0usize, Span::call_site());
    while let Some(top) = stack.last_mut() {
        let Some(tree) = top.tokens.next() else {
            stack.pop();
            continue;
        };
        // The second character of `::`, `->` or `=>` is part of the first's operator.
        let joint = std::mem::take(&mut top.joint);
        if let TokenTree::Punct(p) = &tree {
            if p.spacing() == Spacing::Joint {
                top.joint = Some(p.as_char());
            }
            if matches!(
                (joint, p.as_char()),
                (Some(':'), ':') | (Some('-' | '='), '>')
            ) {
                top.joint = None;
                continue;
            }
        }
        // How a token deepens the statement: `Spine(l)` for the whole rest of it (a binary
        // operator, a keyword, a closure, a generic argument), `Operand(l)` for the rest of the
        // operand it is in (a unary operator, `.`, a call's or an index's group).
        enum Deepens {
            Spine(usize),
            Operand(usize),
        }
        let (deepens, operand, prefix) = match &tree {
            TokenTree::Punct(p) if matches!(p.as_char(), ';' | ',') => {
                // `,` between generic arguments stays within the angle brackets.
                if p.as_char() == ';' || top.angles == 0 {
                    (top.spine, top.operand, top.run, top.angles) = (0, 0, 0, 0);
                }
                top.after_operand = false;
                continue;
            }
            TokenTree::Punct(p) => {
                let c = p.as_char();
                if c == '<' {
                    top.angles += 1;
                    if top.angles > MAX_NESTING {
                        return refuse(
                            p.span(),
                            format!(
                                "generic arguments nested deeper than {MAX_NESTING} levels: the \
                                 compiler refuses a text nested deeper"
                            ),
                        );
                    }
                } else if c == '>' {
                    top.angles = top.angles.saturating_sub(1);
                }
                // An operator after an operand is binary (a level of a chain, which `syn`
                // parses and the lowering walks in a loop), except `.` (a field or a method
                // call: the lowering recurses); one at the start of a statement or after another
                // operator is a prefix, as are a closure's `|` and a generic argument's `<`.
                let deepens = if matches!(c, '|' | '<') {
                    Deepens::Spine(PREFIX_LEVELS)
                } else if !top.after_operand || c == '.' {
                    Deepens::Operand(PREFIX_LEVELS)
                } else {
                    Deepens::Spine(1)
                };
                (deepens, false, !top.after_operand || matches!(c, '|' | '<'))
            }
            TokenTree::Ident(i) if PREFIX_KEYWORDS.iter().any(|k| i == k) => {
                (Deepens::Spine(PREFIX_LEVELS), false, true)
            }
            TokenTree::Ident(_) | TokenTree::Literal(_) => (Deepens::Operand(0), true, false),
            // A call's or an index's arguments after an operand; an operand itself otherwise.
            TokenTree::Group(_) if top.after_operand => {
                (Deepens::Operand(PREFIX_LEVELS), true, false)
            }
            TokenTree::Group(_) => (Deepens::Operand(1), true, false),
        };
        if prefix {
            top.run += 1;
            if top.run > MAX_NESTING {
                return refuse(
                    tree.span(),
                    format!(
                        "more than {MAX_NESTING} prefixes in a row (unary operators, keywords such \
                         as `return`, closures): the compiler refuses a text nested deeper than \
                         {MAX_NESTING} levels; bind parts of the expression with `let`"
                    ),
                );
            }
        } else if operand {
            top.run = 0;
        }
        top.after_operand = operand;
        match deepens {
            Deepens::Spine(l) => {
                top.spine = top.spine.saturating_add(l);
                top.operand = 0;
            }
            Deepens::Operand(l) => top.operand = top.operand.saturating_add(l),
        }
        let at = top
            .base
            .saturating_add(top.spine)
            .saturating_add(top.operand);
        if at > deepest {
            (deepest, deepest_at) = (at, tree.span());
        }
        if let TokenTree::Group(g) = tree {
            if stack.len() > MAX_NESTING {
                let what = match g.delimiter() {
                    Delimiter::Parenthesis => "parentheses",
                    Delimiter::Bracket => "brackets",
                    Delimiter::Brace => "braces",
                    Delimiter::None => "groups",
                };
                return refuse(
                    g.span_open(),
                    format!(
                        "expression nested deeper than {MAX_NESTING} levels ({what} within \
                         parentheses, brackets or braces): the compiler refuses a text nested \
                         deeper; bind inner parts with `let`"
                    ),
                );
            }
            stack.push(frame(g.stream(), at.saturating_add(GROUP_LEVELS)));
        }
    }
    if deepest > MAX_LEVELS {
        return refuse(
            deepest_at,
            format!(
                "the text's longest statement has about {deepest} levels of operators and \
                 groups: the compiler refuses more than {MAX_LEVELS} (a flat sum of about 10⁶ \
                 terms); split long sums into partial sums bound with `let`"
            ),
        );
    }
    Ok(MIN_STACK.saturating_add(deepest.saturating_mul(BYTES_PER_LEVEL)))
}
