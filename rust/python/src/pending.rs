//! The fixes a stream was given ahead of the samples that reach them.

use gyrocore::Fix;

/// Fixes waiting for the samples that reach them, in the order given: a block's new fixes are
/// appended, the ones it used leave from the front. A block works on the waiting fixes where they
/// lie (no copy), so a caller who hands every fix over with the first block pays, per block, for
/// the fixes that block reaches, not for all that wait.
#[derive(Clone, Debug, Default)]
pub(crate) struct Pending {
    fixes: Vec<Fix>,
    /// The first fix still waiting (the ones before it were used).
    start: usize,
}

/// Where the waiting fixes ended before a block's new ones were appended ([`Pending::append`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mark(usize);

impl From<Vec<Fix>> for Pending {
    fn from(fixes: Vec<Fix>) -> Self {
        Pending { fixes, start: 0 }
    }
}

impl Pending {
    /// How many fixes wait.
    pub(crate) fn len(&self) -> usize {
        self.fixes.len() - self.start
    }

    /// The waiting fixes, oldest first.
    pub(crate) fn waiting(&self) -> &[Fix] {
        &self.fixes[self.start..]
    }

    /// Drops every waiting fix.
    pub(crate) fn clear(&mut self) {
        self.fixes.clear();
        self.start = 0;
    }

    /// Appends a block's new fixes after the waiting ones; the mark undoes it
    /// ([`Pending::undo`]) if the block fails.
    pub(crate) fn append(&mut self, new: impl IntoIterator<Item = Fix>) -> Mark {
        let mark = Mark(self.fixes.len());
        self.fixes.extend(new);
        mark
    }

    /// Removes the fixes appended since `mark`: the block failed and changed nothing.
    pub(crate) fn undo(&mut self, mark: Mark) {
        self.fixes.truncate(mark.0);
    }

    /// How many fixes waited before the block that took `mark` appended its own.
    pub(crate) fn before(&self, mark: Mark) -> usize {
        mark.0 - self.start
    }

    /// The block used the first `used` waiting fixes: they leave. The storage is compacted once
    /// the used ones fill half of it, so each fix is moved a bounded number of times on average.
    pub(crate) fn consume(&mut self, used: usize) {
        self.start = (self.start + used).min(self.fixes.len());
        if self.start > self.fixes.len() / 2 {
            self.fixes.drain(..self.start);
            self.start = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(t: f64) -> Fix {
        Fix {
            t,
            heading: 0.0,
            sigma: 0.1,
        }
    }

    fn times(p: &Pending) -> Vec<f64> {
        p.waiting().iter().map(|f| f.t).collect()
    }

    #[test]
    fn used_fixes_leave_from_the_front_and_a_failed_block_leaves_no_trace() {
        let mut p = Pending::default();
        let mark = p.append([fix(1.0), fix(2.0), fix(3.0)]);
        assert_eq!(p.before(mark), 0);
        p.consume(1);
        assert_eq!(times(&p), [2.0, 3.0]);
        let mark = p.append([fix(4.0)]);
        assert_eq!(p.before(mark), 2);
        p.undo(mark);
        assert_eq!(times(&p), [2.0, 3.0]);
        p.consume(2);
        assert_eq!(p.len(), 0);
        p.append((5..9).map(|t| fix(t as f64)));
        p.consume(1);
        assert_eq!(times(&p), [6.0, 7.0, 8.0]);
        p.clear();
        assert_eq!(p.len(), 0);
    }
}
