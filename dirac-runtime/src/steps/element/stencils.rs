//! The stencils of an element-wise system checked against its dimension before a run, and the
//! memory its workspace will take: one pass over the elements that records the first stencil
//! out of range and keeps of each family what the caller asks for (its elements, for the
//! workspace [`super::ElementWorkspace`], or only its shape, for the checks).

use super::assembly::FamilyData;
use super::{ElementLagrangian, Family, FamilyVisitor};
use crate::error::StepError;

/// A pass over the elements that records the first stencil out of `0..n` and keeps of each
/// family all of it ([`FamilyData`], for the workspace) or its shape ([`FamilyShape`]).
pub(super) struct FamilyPass<T> {
    n: usize,
    pub(super) families: Vec<T>,
    pub(super) invalid: Option<String>,
}

impl<T> FamilyPass<T> {
    pub(super) fn new(n: usize) -> Self {
        Self {
            n,
            families: Vec::new(),
            invalid: None,
        }
    }
}

/// What a [`FamilyPass`] keeps of a family.
pub(super) trait Kept {
    /// Nothing yet of a family of stencil width `width` and loop depth `depth`.
    fn family(width: usize, depth: usize) -> Self;
    /// One more element: its loop `indices` and its `stencil` on a system of `n` coordinates.
    fn element(&mut self, indices: &[i64], stencil: &[i64], n: usize);
}

impl Kept for FamilyData {
    fn family(width: usize, depth: usize) -> Self {
        FamilyData {
            width,
            depth,
            count: 0,
            indices: Vec::new(),
            stencils: Vec::new(),
            positions: Vec::new(),
        }
    }

    /// A slot out of range (or missing) reads coordinate 0 (the run is refused before any
    /// step), so that every element keeps exactly `width` slots and `depth` indices.
    fn element(&mut self, indices: &[i64], stencil: &[i64], n: usize) {
        self.count += 1;
        self.indices
            .extend((0..self.depth).map(|d| indices.get(d).copied().unwrap_or(0)));
        self.stencils.extend(
            (0..self.width).map(|a| stencil.get(a).and_then(|&g| coordinate(g, n)).unwrap_or(0)),
        );
    }
}

impl<T: Kept> FamilyVisitor for FamilyPass<T> {
    fn family<F: Family>(&mut self, family: &F) {
        let (n, index) = (self.n, self.families.len());
        let (width, depth) = (family.width(), family.depth());
        let mut kept = T::family(width, depth);
        let invalid = &mut self.invalid;
        family.elements(&mut |indices, stencil| {
            kept.element(indices, stencil, n);
            if invalid.is_some() {
                return;
            }
            if stencil.len() != width || indices.len() != depth {
                *invalid = Some(format!(
                    "element {indices:?} of family {index} reads {} coordinates in {} loops; its \
                     family reads {width} in {depth}",
                    stencil.len(),
                    indices.len()
                ));
                return;
            }
            if let Some((slot, &g)) = stencil
                .iter()
                .enumerate()
                .find(|&(_, &g)| coordinate(g, n).is_none())
            {
                *invalid = Some(outside(indices, index, slot, g, n));
            }
        });
        self.families.push(kept);
    }
}

/// The coordinate a stencil's slot reads, `g`, when it lies in `0..n`.
pub(super) fn coordinate(g: i64, n: usize) -> Option<usize> {
    usize::try_from(g).ok().filter(|&g| g < n)
}

/// Why the stencil of element `indices` of family `index` is refused: its `slot` reads the
/// coordinate `g`, outside `0..n`.
fn outside(indices: &[i64], index: usize, slot: usize, g: i64, n: usize) -> String {
    format!(
        "element {indices:?} of family {index} reads coordinate {g} (slot {slot}), outside 0..{n}: the sizes are too small for its stencil"
    )
}

/// The shape of one family of elements: stencil width, loop depth and number of elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct FamilyShape {
    width: usize,
    depth: usize,
    count: usize,
}

impl Kept for FamilyShape {
    fn family(width: usize, depth: usize) -> Self {
        FamilyShape {
            width,
            depth,
            count: 0,
        }
    }

    fn element(&mut self, _indices: &[i64], _stencil: &[i64], _n: usize) {
        self.count += 1;
    }
}

/// Every stencil against the system's dimension: `Err` with the first one out of range, else
/// the shape of every family. One pass over the elements that stores none of them, so the check
/// costs no memory whatever the sizes (the workspace's size is checked next, [`check_memory`]).
pub(super) fn check_stencils<L: ElementLagrangian>(system: &L) -> Result<Vec<FamilyShape>, String> {
    let mut pass = FamilyPass::<FamilyShape>::new(system.dim());
    system.families(&mut pass);
    pass.invalid.map_or(Ok(pass.families), Err)
}

/// The bytes a run of a system of `n` coordinates with the families `shapes` allocates before
/// its first step, counted from what [`ElementWorkspace::new`] builds (in 8-byte words): per
/// element its loop indices (`depth`), stencil (`width`) and Jacobian positions (`width²`);
/// the pattern's `E = Σ count·width² + n` entries as `(column, row)` pairs while it is sorted
/// (2E), its row indices and column pointers twice (the solver keeps a copy: 2E + 2(n + 1)),
/// the Jacobian's values (E); the residual, next momentum, the (−) step's point and the two
/// increments of the guess (5n) and the driver's second state (2n). The sparse factors' fill comes on top, so this is a
/// lower bound of the run's memory. In `u128`, so no count overflows.
pub(super) fn workspace_bytes(n: usize, shapes: &[FamilyShape]) -> u128 {
    let n = n as u128;
    let mut words = 0u128;
    let mut entries = n;
    for f in shapes {
        let (w, d, c) = (f.width as u128, f.depth as u128, f.count as u128);
        words += c * (d + w + w * w);
        entries += c * w * w;
    }
    words += 2 * entries + 2 * entries + 2 * (n + 1) + entries;
    words += 5 * n + 2 * n;
    8 * words
}

/// Whether the memory a run of `n` coordinates and the families `shapes` needs
/// ([`workspace_bytes`]) can be allocated: it is reserved once, untouched, and released, before
/// anything is built. An address-space limit (`ulimit -v`) or a kernel that refuses to commit
/// that much then gives [`StepError::OutOfMemory`] with the bytes needed, where building the
/// workspace would abort the process.
pub(super) fn check_memory(n: usize, shapes: &[FamilyShape]) -> Result<(), StepError> {
    let bytes = workspace_bytes(n, shapes);
    if crate::linalg::allocatable(bytes) {
        Ok(())
    } else {
        Err(StepError::OutOfMemory {
            what: format!(
                "the run's workspace for {n} coordinates and {} elements (stencils, the step \
                 Jacobian's pattern and values, the step's vectors; the sparse factors come on top)",
                shapes.iter().map(|f| f.count as u128).sum::<u128>()
            ),
            bytes,
        })
    }
}
