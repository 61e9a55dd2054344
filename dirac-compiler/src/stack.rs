//! Enough stack for deep expressions. A body pasted from a computer-algebra system can be a flat
//! sum of 10⁴ terms, which syn parses into a left-nested tree 10⁴ deep; cloning, printing and
//! dropping that tree (syn's derived impls), and lowering it, recurse once per level. rustc runs
//! a procedural macro on whatever stack it has left — its own recursion guard only promises
//! 100 KiB — and a few thousand levels overflowed it (SIGSEGV). So every expansion runs on a
//! stack sized by its input: [`stacker`] (what rustc itself uses) switches to a fresh segment on
//! the same thread when the current one is too small. Not another thread: the `proc_macro` spans
//! the expansion creates belong to this one.

use proc_macro2::{TokenStream, TokenTree};

/// Stack per token of the input: a generous allowance for the frames of one level of nesting (a
/// level takes at least three tokens, `a + b`). Measured with the attribute built unoptimized
/// (as Cargo builds proc macros by default) and rustc's default stack: before this module, a
/// 3,000-term flat sum overflowed (SIGSEGV); with it, 3,000 and 4,500 terms compile, and so do
/// 10,000 (with `RUST_MIN_STACK` for rustc's own parser). The reservation is address space only:
/// pages are committed when touched.
const BYTES_PER_TOKEN: usize = 4 * 1024;

/// What every expansion gets at least: more than any small system needs.
const MIN_STACK: usize = 8 * 1024 * 1024;

/// Runs `f` with at least the stack `args` and `item` could need (see the module documentation).
pub fn run<R>(args: &TokenStream, item: &TokenStream, f: impl FnOnce() -> R) -> R {
    let need = MIN_STACK.max(BYTES_PER_TOKEN.saturating_mul(tokens(args) + tokens(item)));
    stacker::maybe_grow(need, need, f)
}

/// The number of tokens, nested groups included; iterative, since the nesting may be deep too.
fn tokens(stream: &TokenStream) -> usize {
    let mut count = 0;
    let mut pending = vec![stream.clone()];
    while let Some(stream) = pending.pop() {
        for tree in stream {
            count += 1;
            if let TokenTree::Group(g) = tree {
                pending.push(g.stream());
            }
        }
    }
    count
}
