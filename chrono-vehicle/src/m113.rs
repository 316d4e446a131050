//! The M113A1 armoured personnel carrier built from the track templates. Its parameters are
//! data (`data/m113.json`, compiled in): the published figures of the M113A1 where they
//! exist (mass, tread, track width, pitch and shoe counts, ground contact length, sprocket
//! teeth, road wheels, engine rating) and otherwise Project Chrono's M113 model values or a
//! stated assumption; the file's `sources` lists the references and `provenance` names the
//! source of every value.

use crate::error::Result;
use crate::tracked::TrackedVehicleData;

/// The M113A1 description as shipped (`chrono-vehicle/data/m113.json`).
pub const M113_JSON: &str = include_str!("../data/m113.json");

/// The M113A1 description, validated.
pub fn m113_data() -> Result<TrackedVehicleData> {
    let d: TrackedVehicleData = crate::json_path::parse(M113_JSON, "data/m113.json")?;
    d.validate()?;
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every leaf value of the data file has a provenance entry (its own path or a parent's).
    #[test]
    fn every_value_has_a_source() {
        let v: serde_json::Value = serde_json::from_str(M113_JSON).unwrap();
        let prov = v["provenance"].as_object().unwrap();
        fn leaves(v: &serde_json::Value, path: String, out: &mut Vec<String>) {
            match v {
                serde_json::Value::Object(m) => {
                    for (k, x) in m {
                        let p = if path.is_empty() {
                            k.clone()
                        } else {
                            format!("{path}.{k}")
                        };
                        leaves(x, p, out);
                    }
                }
                _ => out.push(path),
            }
        }
        let mut all = Vec::new();
        for key in [
            "published",
            "chassis",
            "track_y",
            "track",
            "powertrain",
            "driveline",
            "hull",
            "obstacle",
        ] {
            leaves(&v[key], key.to_string(), &mut all);
        }
        for p in all {
            let mut q = p.as_str();
            let found = loop {
                if prov.contains_key(q) {
                    break true;
                }
                match q.rfind('.') {
                    Some(i) => q = &q[..i],
                    None => break false,
                }
            };
            assert!(found, "no provenance for `{p}`");
        }
        assert!(m113_data().is_ok());
    }
}
