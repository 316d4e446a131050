//! Reading vehicle data with errors that name the field: the path of the value that failed
//! to deserialize (`axles[0].suspension.spring`), tracked during deserialization by
//! `serde_path_to_error`, with serde_json's message and position.

/// Parse `text` (JSON read from `path`) into `T`; a parse error names `path`, the field
/// path of the failing value and what serde_json said.
pub(crate) fn parse<T: serde::de::DeserializeOwned>(
    text: &str,
    path: &str,
) -> crate::error::Result<T> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let parsed: Result<T, _> = serde_path_to_error::deserialize(&mut *de);
    let value = parsed.map_err(|e| {
        let at = e.path().to_string();
        let inner = e.into_inner();
        // `.` is the path of the top level (a syntax error or a missing top-level field).
        let message = if at.is_empty() || at == "." {
            inner.to_string()
        } else {
            format!("at `{at}`: {inner}")
        };
        crate::error::VehicleError::Data {
            path: path.to_string(),
            message,
        }
    })?;
    // Trailing characters after the value are an error too (as in serde_json::from_str).
    de.end().map_err(|e| crate::error::VehicleError::Data {
        path: path.to_string(),
        message: e.to_string(),
    })?;
    Ok(value)
}

#[cfg(test)]
mod tests {
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    #[allow(dead_code)]
    struct A {
        a: B,
    }
    #[derive(Debug, Deserialize)]
    #[allow(dead_code)]
    struct B {
        b: Vec<f64>,
        c: f64,
    }

    fn err(text: &str) -> String {
        super::parse::<A>(text, "t.json").unwrap_err().to_string()
    }

    #[test]
    fn errors_name_the_member_path() {
        let e = err("{\"a\": {\"b\": [1, 2, \"x\"], \"c\": 3}}");
        assert!(e.contains("a.b[2]") && e.contains("t.json"), "{e}");
        // A map where a number belongs: the path of the number, not of its container.
        let e = err("{\"a\": {\"b\": [], \"c\": {\"x\": 1}}}");
        assert!(e.contains("a.c"), "{e}");
        let e = err("{\"a\": {\"b\": []}}");
        assert!(e.contains("`a`") && e.contains("c"), "{e}");
        assert!(err("{\"a\": {\"b\": [], \"c\": 1}} x").contains("trailing"));
        assert!(super::parse::<A>("{\"a\": {\"b\": [1], \"c\": 2}}", "t").is_ok());
    }
}
