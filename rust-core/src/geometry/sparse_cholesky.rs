//! The sparse Cholesky factorization `A = L Lᵀ` (faer's sparse LLᵀ,
//! simplicial or supernodal as the sparsity suits) that every linear system
//! of the geometry and the avatar stage is solved with: deformation
//! transfer, both steps of the partial transfer, the non-rigid
//! registration, the mask pulled onto the skin and the person's rest field.
//! Each builds the lower triangle of a symmetric positive definite `n × n`
//! matrix as triplets (duplicates are summed) and factors it once; a solve
//! is then two triangular sweeps per right-hand side. Where the values
//! change but the sparsity does not (the registration's steps, the
//! person's rest field's solves), the pattern is analysed once
//! ([`FixedPattern`]): where each entry's value goes and the symbolic
//! factorization; each new set of values is then only summed into place
//! and factored numerically, into storage kept from one factorization to
//! the next ([`FactorWork`]).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    LltRef, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Pair, SparseColMat, SparseColMatRef, SymbolicSparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

/// Why a matrix could not be factored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FactorError {
    /// An entry lies outside the `n × n` matrix, or the matrix is too large
    /// to index.
    #[error("the matrix's entries do not fit it: {0}")]
    Entries(String),
    /// The sparsity pattern could not be analysed.
    #[error("the symbolic factorization failed: {0}")]
    Symbolic(String),
    /// The numeric factorization failed: the matrix is not positive
    /// definite (or holds a NaN).
    #[error("the matrix is not positive definite: {0}")]
    Numeric(String),
}

/// The `n × n` matrix whose lower triangle is `lower` (duplicates summed).
fn matrix(
    n: usize,
    lower: &[Triplet<usize, usize, f64>],
) -> Result<SparseColMat<usize, f64>, FactorError> {
    SparseColMat::try_new_from_triplets(n, n, lower)
        .map_err(|e| FactorError::Entries(format!("{e:?}")))
}

/// The lower triangle of an `n × n` symmetric matrix whose entries are
/// always at the same places, in the same order, analysed once: where
/// each entry's value goes (duplicates summed) and the symbolic
/// factorization. [`FixedPattern::factor`] then takes only the values,
/// into storage kept from one factorization to the next
/// ([`FactorWork`]).
pub struct FixedPattern {
    structure: SymbolicSparseColMat<usize>,
    /// For each entry, in the order given, its place among the matrix's
    /// stored values.
    place: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
}

/// What the factorizations of one [`FixedPattern`] reuse: the matrix's
/// values, the factor's and the scratch space, allocated once.
pub struct FactorWork {
    matrix: Vec<f64>,
    factor: Vec<f64>,
    scratch: MemBuffer,
}

/// `L Lᵀ` of a [`FixedPattern`]'s matrix, held in its [`FactorWork`].
pub struct FixedFactor<'a> {
    llt: LltRef<'a, usize, f64>,
    scratch: &'a mut MemBuffer,
}

impl FixedFactor<'_> {
    /// Solves `A x = b` for every column `b` of `rhs`, in place.
    pub fn solve_in_place(&mut self, rhs: MatMut<'_, f64>) {
        self.llt
            .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(self.scratch));
    }
}

impl FixedPattern {
    /// Analyses the pattern of the `n × n` matrix whose lower triangle has
    /// entries at `lower`'s places (their values do not matter).
    pub fn new(n: usize, lower: &[Triplet<usize, usize, f64>]) -> Result<Self, FactorError> {
        let places: Vec<Pair<usize, usize>> = lower
            .iter()
            .map(|t| Pair {
                row: t.row,
                col: t.col,
            })
            .collect();
        let (structure, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &places)
            .map_err(|e| FactorError::Entries(format!("{e:?}")))?;
        // Each entry's place: its row among its column's (sorted, unique).
        let (starts, rows) = (structure.col_ptr(), structure.row_idx());
        let place = places
            .iter()
            .map(|p| {
                let column = &rows[starts[p.col]..starts[p.col + 1]];
                column
                    .binary_search(&p.row)
                    .map(|k| starts[p.col] + k)
                    .map_err(|_| FactorError::Entries(format!("no place for {p:?}")))
            })
            .collect::<Result<Vec<usize>, FactorError>>()?;
        let symbolic = factorize_symbolic_cholesky(
            structure.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| FactorError::Symbolic(format!("{e:?}")))?;
        Ok(FixedPattern {
            structure,
            place,
            symbolic,
        })
    }

    /// Storage for this pattern's factorizations: its matrix's values, its
    /// factor's, and the scratch space of a factorization and of a solve
    /// with up to `columns` right-hand sides.
    pub fn work(&self, columns: usize) -> FactorWork {
        let scratch = StackReq::any_of(&[
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            self.symbolic
                .solve_in_place_scratch::<f64>(columns, Par::Seq),
        ]);
        FactorWork {
            matrix: vec![0.0; self.structure.row_idx().len()],
            factor: vec![0.0; self.symbolic.len_val()],
            scratch: MemBuffer::new(scratch),
        }
    }

    /// `L Lᵀ` of the matrix whose entries, at the places and in the order
    /// the pattern was made with, have the values `values`, in `work`
    /// ([`FixedPattern::work`]).
    pub fn factor<'a>(
        &'a self,
        values: &[f64],
        work: &'a mut FactorWork,
    ) -> Result<FixedFactor<'a>, FactorError> {
        if values.len() != self.place.len() {
            return Err(FactorError::Entries(format!(
                "{} values for a pattern of {} entries",
                values.len(),
                self.place.len()
            )));
        }
        work.matrix.fill(0.0);
        for (&k, &x) in self.place.iter().zip(values) {
            work.matrix[k] += x;
        }
        self.numeric(work)
    }

    /// `L Lᵀ` of the matrix whose lower triangle is `entries` (duplicates
    /// summed, as [`factor`] sums them: the same matrix to the bit), in
    /// `work`; an error if its pattern is not this one. Only the symbolic
    /// analysis is saved, not the matrix's assembly.
    pub fn factor_entries<'a>(
        &'a self,
        entries: &[Triplet<usize, usize, f64>],
        work: &'a mut FactorWork,
    ) -> Result<FixedFactor<'a>, FactorError> {
        let n = self.structure.ncols();
        let a = matrix(n, entries)?;
        if a.symbolic().col_ptr() != self.structure.col_ptr()
            || a.symbolic().row_idx() != self.structure.row_idx()
        {
            return Err(FactorError::Entries(
                "the entries' pattern is not the one analysed".into(),
            ));
        }
        work.matrix.copy_from_slice(a.val());
        self.numeric(work)
    }

    /// The numeric factorization of the values in `work`.
    fn numeric<'a>(&'a self, work: &'a mut FactorWork) -> Result<FixedFactor<'a>, FactorError> {
        let FactorWork {
            matrix,
            factor,
            scratch,
        } = work;
        let a = SparseColMatRef::new(self.structure.as_ref(), matrix);
        let llt = self
            .symbolic
            .factorize_numeric_llt(
                factor,
                a,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(scratch),
                Default::default(),
            )
            .map_err(|e| FactorError::Numeric(format!("{e:?}")))?;
        Ok(FixedFactor { llt, scratch })
    }
}

/// `L Lᵀ` of the `n × n` matrix with lower triangle `lower`.
pub fn factor(
    n: usize,
    lower: &[Triplet<usize, usize, f64>],
) -> Result<Llt<usize, f64>, FactorError> {
    let a = matrix(n, lower)?;
    let symbolic = SymbolicLlt::try_new(a.symbolic(), Side::Lower)
        .map_err(|e| FactorError::Symbolic(format!("{e:?}")))?;
    Llt::try_new_with_symbolic(symbolic, a.as_ref(), Side::Lower)
        .map_err(|e| FactorError::Numeric(format!("{e:?}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;
    use faer::linalg::solvers::Solve;

    /// The 1D Laplacian plus identity, lower triangle: tridiagonal 3, −1.
    fn tridiagonal(n: usize, diagonal: f64) -> Vec<Triplet<usize, usize, f64>> {
        let mut t: Vec<_> = (0..n).map(|i| Triplet::new(i, i, diagonal)).collect();
        t.extend((1..n).map(|i| Triplet::new(i, i - 1, -1.0)));
        t
    }

    #[test]
    fn a_factored_system_solves_and_duplicates_are_summed() {
        let n = 5;
        let mut lower = tridiagonal(n, 2.0);
        lower.extend((0..n).map(|i| Triplet::new(i, i, 1.0)));
        let llt = factor(n, &lower).expect("positive definite");
        // A x = b for x = 1: row sums of [−1 3 −1].
        let mut b = Mat::<f64>::from_fn(n, 1, |i, _| if i == 0 || i == n - 1 { 2.0 } else { 1.0 });
        llt.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[(i, 0)] - 1.0).abs() < 1e-12, "{i}: {}", b[(i, 0)]);
        }
        // The same pattern, analysed once, factored twice in the same
        // storage, the second time with every value tripled: x = ⅓,
        // whatever the first (doubled) left there.
        let pattern = FixedPattern::new(n, &lower).unwrap();
        let mut work = pattern.work(1);
        let doubled: Vec<f64> = lower.iter().map(|t| 2.0 * t.val).collect();
        pattern.factor(&doubled, &mut work).unwrap();
        let tripled: Vec<f64> = lower.iter().map(|t| 3.0 * t.val).collect();
        let mut again = pattern.factor(&tripled, &mut work).unwrap();
        let mut c = Mat::<f64>::from_fn(n, 1, |i, _| if i == 0 || i == n - 1 { 2.0 } else { 1.0 });
        again.solve_in_place(c.as_mut());
        for i in 0..n {
            assert!((c[(i, 0)] - 1.0 / 3.0).abs() < 1e-12, "{i}: {}", c[(i, 0)]);
        }
        assert!(matches!(
            pattern.factor(&doubled[1..], &mut work),
            Err(FactorError::Entries(_))
        ));
        // An indefinite set of values is a typed error, and the storage
        // still serves the next.
        let negative: Vec<f64> = lower.iter().map(|t| -t.val).collect();
        assert!(matches!(
            pattern.factor(&negative, &mut work),
            Err(FactorError::Numeric(_))
        ));
        assert!(pattern.factor(&doubled, &mut work).is_ok());
    }

    #[test]
    fn an_indefinite_matrix_or_an_entry_outside_is_a_typed_error() {
        let indefinite = tridiagonal(4, -1.0);
        assert!(matches!(
            factor(4, &indefinite),
            Err(FactorError::Numeric(_))
        ));
        let outside = vec![Triplet::new(7, 0, 1.0)];
        assert!(matches!(factor(4, &outside), Err(FactorError::Entries(_))));
    }

    /// Entries in another order, with other duplicates, but the same
    /// pattern: the same factor as [`factor`]'s, to the bit; a pattern
    /// with an entry more is refused.
    #[test]
    fn entries_of_the_same_pattern_factor_as_a_new_matrix_would() {
        let n = 6;
        let pattern = FixedPattern::new(n, &tridiagonal(n, 4.0)).unwrap();
        let mut work = pattern.work(1);
        let mut entries = tridiagonal(n, 3.0);
        entries.reverse();
        entries.extend((0..n).map(|i| Triplet::new(i, i, 0.1 * i as f64)));
        entries.push(Triplet::new(3, 2, -0.25));
        let rhs = || Mat::<f64>::from_fn(n, 1, |i, _| (i as f64).sin() + 1.0);
        let (mut x, mut y) = (rhs(), rhs());
        factor(n, &entries).unwrap().solve_in_place(&mut x);
        let mut fixed = pattern.factor_entries(&entries, &mut work).unwrap();
        fixed.solve_in_place(y.as_mut());
        for i in 0..n {
            assert_eq!(x[(i, 0)].to_bits(), y[(i, 0)].to_bits(), "{i}");
        }
        entries.push(Triplet::new(5, 0, 0.01));
        assert!(matches!(
            pattern.factor_entries(&entries, &mut work),
            Err(FactorError::Entries(_))
        ));
    }
}
