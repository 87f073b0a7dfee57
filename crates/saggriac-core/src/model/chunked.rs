//! Append-only rows kept in fixed-size chunks that snapshots share. The memory only grows, so an
//! evaluation of the model at step t can read the first n_t samples while learning goes on:
//! cloning a `Chunked` copies one pointer per chunk, and the writer copies a chunk only when it
//! must change one that a snapshot still holds (only the last, partly filled chunk ever changes).
//! Each chunk is allocated at its full size once, so no capacity is wasted beyond the last chunk.

use std::sync::Arc;

#[derive(Debug, Clone)]
pub struct Chunked<T> {
    width: usize,
    rows_per_chunk: usize,
    chunks: Vec<Arc<Vec<T>>>,
    len: usize,
}

impl<T: Copy> Chunked<T> {
    /// Rows of `width` values, `rows_per_chunk` rows to a chunk.
    pub fn new(width: usize, rows_per_chunk: usize) -> Self {
        assert!(rows_per_chunk > 0);
        Chunked { width, rows_per_chunk, chunks: Vec::new(), len: 0 }
    }

    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    pub fn width(&self) -> usize {
        self.width
    }

    /// The last chunk, for writing: copied first if a snapshot shares it, with its full capacity.
    fn last_chunk(&mut self) -> &mut Vec<T> {
        let cap = self.width * self.rows_per_chunk;
        let last = Arc::make_mut(self.chunks.last_mut().expect("a chunk exists"));
        if last.capacity() < cap {
            last.reserve_exact(cap - last.len());
        }
        last
    }

    /// Append one row.
    pub fn push(&mut self, row: &[T]) {
        debug_assert_eq!(row.len(), self.width);
        if self.len % self.rows_per_chunk == 0 {
            self.chunks.push(Arc::new(Vec::with_capacity(self.width * self.rows_per_chunk)));
        }
        self.last_chunk().extend_from_slice(row);
        self.len += 1;
    }

    /// Row `i`.
    #[inline]
    pub fn row(&self, i: usize) -> &[T] {
        let (c, r) = (i / self.rows_per_chunk, i % self.rows_per_chunk);
        &self.chunks[c][r * self.width..(r + 1) * self.width]
    }

    /// The last row, for writing.
    pub fn last_mut(&mut self) -> &mut [T] {
        let w = self.width;
        let chunk = self.last_chunk();
        let start = chunk.len() - w;
        &mut chunk[start..]
    }

    /// Every row, in order, as one flat vector.
    pub fn to_vec(&self) -> Vec<T> {
        self.chunks.iter().flat_map(|c| c.iter().copied()).collect()
    }

    /// Bytes allocated for the values (the chunks at their capacity).
    pub fn bytes(&self) -> usize {
        self.chunks.iter().map(|c| c.capacity()).sum::<usize>() * std::mem::size_of::<T>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_survive_growth_and_snapshots_keep_what_they_saw() {
        let mut c = Chunked::new(3, 4);
        for i in 0..10 {
            c.push(&[i, i + 1, i + 2]);
        }
        let snap = c.clone();
        // The last chunk is shared: writing copies it, the snapshot keeps its rows.
        c.last_mut()[0] = 99;
        c.push(&[7, 7, 7]);
        assert_eq!(snap.len(), 10);
        assert_eq!(snap.row(9), &[9, 10, 11]);
        assert_eq!(c.row(9), &[99, 10, 11]);
        assert_eq!(c.row(10), &[7, 7, 7]);
        assert_eq!(c.row(3), &[3, 4, 5]);
        assert_eq!(c.to_vec().len(), 33);
        // Three chunks of 12 values each (the copied one keeps its full capacity).
        assert_eq!(c.bytes(), 3 * 12 * std::mem::size_of::<i32>());
    }
}
