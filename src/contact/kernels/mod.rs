//! The dense kernels of the contact solver, below the algorithms that use
//! them: the `O(N)` node passes of the exact increment ([`nodes`]), the
//! FFT packing of the operators ([`packing`]), the kept inverse's lanes
//! and triangular passes ([`lanes`]) and a dense LU ([`lu`]). Nothing here
//! imports from the rest of `contact/` but its tolerances.
//!
//! The node passes run with the widest vector instructions the processor has.
//!
//! Every pass over the nodes of an increment (the end margins of a segment,
//! the move along it, the rates of the slip set, the nodes at the friction
//! limit) is a plain loop over a few arrays. The release build targets the
//! baseline `x86_64` (SSE2, two lanes); each pass here is compiled once per
//! instruction set that [`pulp::Arch`] knows (AVX2 with four lanes among
//! them) and the best is chosen at run time, so one binary runs on any
//! `x86_64` and uses AVX2 where it exists. The two passes that dominate an
//! increment ([`end_margins`] and [`slide`]) are written in `pulp`'s
//! vectors, because the compiler does not vectorise them by itself; the
//! rest are loops it vectorises, as are the passes that pack a slip vector
//! into the FFT of [`super::operators`] and its responses out of it.
//!
//! Results do not depend on the instruction set: every lane does the scalar
//! operations in the scalar order (no fused multiply-add is formed: Rust
//! does not contract `a * b + c`), minima do not depend on order, and the
//! one sum (the dissipation of a move) is kept in four lanes on every
//! processor. The tests compare the bits on the dispatched, the
//! scalar and emulated two- and four-lane instruction sets.

/// Defines `pub(in crate::contact) fn $name(args) -> out { body }` with `body` compiled
/// once for each instruction set [`pulp::Arch`] knows and the best chosen
/// at run time. The body goes into a [`pulp::WithSimd`] operation whose
/// `with_simd` is generic over the instruction set and always inlined, so
/// every copy is inlined into a function compiled for its instruction set
/// (a closure would be compiled once, for the baseline, and called from
/// each).
macro_rules! wide {
    ($(#[$doc:meta])* fn $name:ident<$lt:lifetime>($($arg:ident: $ty:ty),* $(,)?) -> $out:ty $body:block) => {
        $(#[$doc])*
        pub(in crate::contact) fn $name<$lt>($($arg: $ty),*) -> $out {
            struct Op<$lt> {
                $($arg: $ty,)*
            }
            impl<$lt> pulp::WithSimd for Op<$lt> {
                type Output = $out;
                #[inline(always)]
                fn with_simd<S: pulp::Simd>(self, _: S) -> $out {
                    let Op { $($arg),* } = self;
                    $body
                }
            }
            pulp::Arch::new().dispatch(Op { $($arg),* })
        }
    };
}

mod lanes;
mod lu;
mod nodes;
mod packing;
#[cfg(test)]
mod tests;

pub(super) use lanes::*;
pub(super) use lu::DenseLu;
pub(super) use nodes::*;
pub(super) use packing::*;

/// The whole groups of four of `s`, as arrays (no length checks in a loop
/// over them).
#[inline(always)]
pub(in crate::contact) fn four(s: &[f64]) -> &[[f64; 4]] {
    s.as_chunks::<4>().0
}
