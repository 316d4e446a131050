//! A map from keys to values kept as a vector sorted by key: the warm-start cache of the
//! NSC contacts ([`super::nsc::WarmStartCache`]).
//!
//! The contacts of a step come in key order for the sphere grid (pairs sorted by collider),
//! so a lookup usually hits the entry right after the previous one and costs one
//! comparison; otherwise it is a binary search. Compared with a hash map: no hashing, no
//! allocation per step once grown, and iteration in key order (deterministic).

/// Values by unique key, in a vector sorted by key.
#[derive(Debug, Clone)]
pub(crate) struct SortedMap<K, V> {
    entries: Vec<(K, V)>,
}

impl<K, V> Default for SortedMap<K, V> {
    fn default() -> Self {
        Self {
            entries: Vec::new(),
        }
    }
}

impl<K: Ord + Copy, V: Copy> SortedMap<K, V> {
    /// Number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Remove every entry (keeps the allocation).
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Append an entry; call [`finish`](Self::finish) after the last one before a lookup.
    pub fn push(&mut self, key: K, value: V) {
        self.entries.push((key, value));
    }

    /// Replace the entries by `f(0), .., f(n - 1)` (in that order, computed in parallel;
    /// capacity kept), then [`finish`](Self::finish): the same map as clearing and pushing
    /// them one by one.
    pub fn fill_par(&mut self, n: usize, f: impl Fn(usize) -> (K, V) + Sync + Send)
    where
        K: Send + Sync,
        V: Send + Sync,
    {
        use rayon::prelude::*;
        self.entries.clear();
        self.entries
            .par_extend((0..n).into_par_iter().with_min_len(1024).map(f));
        self.finish();
    }

    /// Restore the order after [`push`](Self::push)es: sort by key and, of equal keys,
    /// keep the last pushed (what a map's insert would keep). Free when already sorted.
    pub fn finish(&mut self) {
        if self.entries.is_sorted_by(|a, b| a.0 < b.0) {
            return;
        }
        // Stable: equal keys keep their push order, and the last of each run is kept.
        self.entries.sort_by_key(|e| e.0);
        let mut out = 0;
        for i in 0..self.entries.len() {
            let last_of_run =
                i + 1 == self.entries.len() || self.entries[i + 1].0 != self.entries[i].0;
            if last_of_run {
                self.entries[out] = self.entries[i];
                out += 1;
            }
        }
        self.entries.truncate(out);
    }

    /// The value of `key`. `cursor` is a hint: where the previous lookup ended (start at 0
    /// and pass the same variable to lookups in increasing key order).
    pub fn get(&self, key: &K, cursor: &mut usize) -> Option<V> {
        if let Some(e) = self.entries.get(*cursor)
            && e.0 == *key
        {
            *cursor += 1;
            return Some(e.1);
        }
        match self.entries.binary_search_by(|e| e.0.cmp(key)) {
            Ok(i) => {
                *cursor = i + 1;
                Some(self.entries[i].1)
            }
            Err(i) => {
                *cursor = i;
                None
            }
        }
    }

    /// Rewrite every key by `f`, dropping the entries it maps to `None`, and restore the
    /// order.
    pub fn remap(&mut self, f: impl Fn(K) -> Option<K>) {
        self.entries = (self.entries.drain(..))
            .filter_map(|(k, v)| Some((f(k)?, v)))
            .collect();
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn behaves_like_a_map_whatever_the_push_order() {
        // Keys pushed out of order with repeats: the last value of a key wins, as with a
        // map's insert; lookups in any order find every key and reject absent ones.
        let pushes = [
            (5, 1.0),
            (2, 2.0),
            (9, 3.0),
            (2, 4.0),
            (7, 5.0),
            (5, 6.0),
            (1, 7.0),
        ];
        let mut m = SortedMap::default();
        let mut h = HashMap::new();
        for &(k, v) in &pushes {
            m.push(k, v);
            h.insert(k, v);
        }
        m.finish();
        assert_eq!(m.len(), h.len());
        let mut cursor = 0;
        for k in 0..12 {
            assert_eq!(m.get(&k, &mut cursor), h.get(&k).copied(), "key {k}");
        }
        for k in (0..12).rev() {
            assert_eq!(m.get(&k, &mut cursor), h.get(&k).copied(), "key {k}");
        }
    }

    #[test]
    fn in_order_lookups_take_the_hint_and_remap_keeps_the_order() {
        let mut m = SortedMap::default();
        for k in 0..100u32 {
            m.push(2 * k, k);
        }
        m.finish();
        let mut cursor = 0;
        for k in 0..100u32 {
            assert_eq!(m.get(&(2 * k), &mut cursor), Some(k));
            assert_eq!(cursor, k as usize + 1);
        }
        // Reverse the keys and drop the multiples of 3: still sorted, still found.
        m.remap(|k| (k % 3 != 0).then_some(1000 - k));
        let mut cursor = 0;
        for k in 0..100u32 {
            let want = ((2 * k) % 3 != 0).then_some(k);
            assert_eq!(m.get(&(1000 - 2 * k), &mut cursor), want);
        }
        m.clear();
        assert_eq!(m.len(), 0);
        assert_eq!(m.get(&4, &mut 0), None);
    }

    #[test]
    fn a_parallel_fill_equals_the_serial_pushes() {
        // Keys out of order with repeats.
        let key = |i: usize| ((i * 7919) % 5003) as u32;
        let (mut serial, mut par) = (SortedMap::default(), SortedMap::default());
        for i in 0..6000 {
            serial.push(key(i), i);
        }
        serial.finish();
        par.fill_par(6000, |i| (key(i), i));
        assert_eq!(serial.entries, par.entries);
    }
}
