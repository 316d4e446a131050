//! Generated mutations of a JSON document, for fuzzing the readers of scene files
//! (vehicle descriptions, CCP problem files): every reader must turn a mutated document
//! into a value or into an error that names the mutated field, never a panic.
//!
//! A test lists every path of a valid document ([`paths`]), picks one and a [`Mutation`]
//! from its generator, applies it ([`mutate`]) and checks the reader's error message with
//! [`error_names_path`].

use serde_json::Value;

/// One step of a path into a JSON value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Seg {
    /// A member of an object.
    Key(String),
    /// An element of an array.
    Index(usize),
}

/// A change to the value at a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mutation {
    /// Remove the member (or array element).
    Delete,
    /// A number made negative (`-|x| - 1`).
    Negative,
    /// A number set to zero.
    Zero,
    /// A number set to `1e308` (JSON has no NaN: the largest finite values stand in).
    Huge,
    /// A number set to `-1e308`.
    NegHuge,
    /// The value replaced by a string.
    Text,
    /// An array cut to half its length.
    Truncate,
    /// A string replaced by a name no enum has.
    UnknownName,
    /// The value wrapped in an object.
    NestObject,
    /// The value wrapped in an array.
    NestArray,
}

/// Every [`Mutation`], for a generator to index.
pub const MUTATIONS: [Mutation; 10] = [
    Mutation::Delete,
    Mutation::Negative,
    Mutation::Zero,
    Mutation::Huge,
    Mutation::NegHuge,
    Mutation::Text,
    Mutation::Truncate,
    Mutation::UnknownName,
    Mutation::NestObject,
    Mutation::NestArray,
];

/// Every path of `v`, the root excluded, depth first.
pub fn paths(v: &Value) -> Vec<Vec<Seg>> {
    fn walk(v: &Value, prefix: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
        let mut visit = |seg: Seg, x: &Value, prefix: &mut Vec<Seg>| {
            prefix.push(seg);
            out.push(prefix.clone());
            walk(x, prefix, out);
            prefix.pop();
        };
        match v {
            Value::Object(m) => m
                .iter()
                .for_each(|(k, x)| visit(Seg::Key(k.clone()), x, prefix)),
            Value::Array(a) => a
                .iter()
                .enumerate()
                .for_each(|(i, x)| visit(Seg::Index(i), x, prefix)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(v, &mut Vec::new(), &mut out);
    out
}

fn get_mut<'a>(v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Seg::Key(k) => v.get_mut(k.as_str()),
        Seg::Index(i) => v.get_mut(*i),
    })
}

/// Apply `m` at `path` (a path of `root`, not the root itself); `false` if it does not
/// apply to the value there (e.g. [`Mutation::Zero`] on a string), `root` unchanged.
pub fn mutate(root: &mut Value, path: &[Seg], m: Mutation) -> bool {
    let Some((last, parent)) = path.split_last() else {
        return false;
    };
    if m == Mutation::Delete {
        return match (get_mut(root, parent), last) {
            (Some(Value::Object(o)), Seg::Key(k)) => o.remove(k).is_some(),
            (Some(Value::Array(a)), Seg::Index(i)) if *i < a.len() => {
                a.remove(*i);
                true
            }
            _ => false,
        };
    }
    let Some(v) = get_mut(root, path) else {
        return false;
    };
    let new = match (m, &*v) {
        (Mutation::Negative, Value::Number(n)) => (-n.as_f64().unwrap_or(0.0).abs() - 1.0).into(),
        (Mutation::Zero, Value::Number(_)) => 0.0.into(),
        (Mutation::Huge, Value::Number(_)) => 1e308.into(),
        (Mutation::NegHuge, Value::Number(_)) => (-1e308).into(),
        (Mutation::Text, _) => Value::String("fuzz".into()),
        (Mutation::Truncate, Value::Array(a)) => Value::Array(a[..a.len() / 2].to_vec()),
        (Mutation::UnknownName, Value::String(_)) => Value::String("no_such_kind".into()),
        (Mutation::NestObject, x) => serde_json::json!({ "value": x }),
        (Mutation::NestArray, x) => Value::Array(vec![x.clone()]),
        _ => return false,
    };
    *v = new;
    true
}

/// The object keys along `path`: the names an error about a mutation there may use.
pub fn key_names(path: &[Seg]) -> Vec<String> {
    path.iter()
        .filter_map(|s| match s {
            Seg::Key(k) => Some(k.clone()),
            Seg::Index(_) => None,
        })
        .collect()
}

/// Whether the error message `msg` names the field that mutation `m` at `path` changed:
/// the innermost key of the path, or, for a removed member or a cut array (reported by
/// the object or array that now lacks it), any key along the path.
pub fn error_names_path(msg: &str, path: &[Seg], m: Mutation) -> bool {
    let keys = key_names(path);
    let innermost = keys.last().map(String::as_str).unwrap_or_default();
    msg.contains(innermost)
        || matches!(m, Mutation::Delete | Mutation::Truncate)
            && keys.iter().any(|k| msg.contains(k.as_str()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_and_mutations() {
        let mut v: Value = serde_json::json!({"a": [1.0, 2.0], "b": {"c": "x"}});
        let all = paths(&v);
        assert_eq!(all.len(), 5);
        let c = vec![Seg::Key("b".into()), Seg::Key("c".into())];
        assert!(!mutate(&mut v, &c, Mutation::Zero), "a string has no zero");
        assert!(mutate(&mut v, &c, Mutation::UnknownName));
        assert_eq!(v["b"]["c"], "no_such_kind");
        let a1 = vec![Seg::Key("a".into()), Seg::Index(1)];
        assert!(mutate(&mut v, &a1, Mutation::Negative));
        assert_eq!(v["a"][1], -3.0);
        assert!(mutate(&mut v, &a1, Mutation::Delete));
        assert_eq!(v["a"].as_array().map(Vec::len), Some(1));
        assert!(!mutate(&mut v, &a1, Mutation::Delete), "gone already");
        assert!(!mutate(&mut v, &[], Mutation::Text), "not the root");
        assert!(error_names_path(
            "`b.c`: unknown variant",
            &c,
            Mutation::UnknownName
        ));
        assert!(!error_names_path(
            "something failed",
            &c,
            Mutation::UnknownName
        ));
        assert!(error_names_path(
            "missing field in `a`",
            &a1,
            Mutation::Delete
        ));
    }
}
