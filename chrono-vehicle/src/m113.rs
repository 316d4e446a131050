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
    TrackedVehicleData::from_json(M113_JSON, "data/m113.json")
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

    /// `data/m113.json` with the value at `path` (member names) replaced by `v`, read back.
    fn read_edited(path: &[&str], v: serde_json::Value) -> String {
        let mut d: serde_json::Value = serde_json::from_str(M113_JSON).unwrap();
        let mut x = &mut d;
        for k in path {
            x = &mut x[*k];
        }
        assert!(!x.is_null(), "no value at {path:?}");
        *x = v;
        TrackedVehicleData::from_json(&d.to_string(), "m113-edited.json")
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    }

    /// The bad inputs, read from JSON: each is an error naming the field and the
    /// rejected value (the chain check runs on reading, before any body is built).
    #[test]
    fn bad_track_data_in_the_json_names_the_field_and_value() {
        use serde_json::json;
        // Fewer shoes than the loop needs (the M113's need 63-64), on either side.
        let e = read_edited(&["track", "shoe", "count"], json!([55, 64]));
        assert!(
            e.contains("`track.shoe.count[0]` = 55") && e.contains("too few"),
            "{e}"
        );
        let e = read_edited(&["track", "shoe", "count"], json!([63, 58]));
        assert!(
            e.contains("`track.shoe.count[1]` = 58") && e.contains("too few"),
            "{e}"
        );
        let e = read_edited(&["track", "shoe", "count"], json!([63, 80]));
        assert!(
            e.contains("`track.shoe.count[1]` = 80") && e.contains("too many"),
            "{e}"
        );
        // A tooth count that does not match the pitch at the pitch radius, either way, and
        // a pitch that does not match the teeth.
        for n in [9, 11] {
            let e = read_edited(&["track", "sprocket", "num_teeth"], json!(n));
            assert!(
                e.contains(&format!("`track.sprocket.num_teeth` = {n}")),
                "{e}"
            );
            assert!(e.contains("does not match the shoe pitch"), "{e}");
        }
        let e = read_edited(&["track", "shoe", "pitch"], json!(0.16));
        assert!(
            e.contains("`track.sprocket.num_teeth` = 10") && e.contains("pitch 0.16"),
            "{e}"
        );
        // A negative tensioner preload.
        let e = read_edited(&["track", "idler", "tensioner", "preload"], json!(-2.0e4));
        assert!(
            e.contains("`track.idler.tensioner.preload` = -20000"),
            "{e}"
        );
        // A value of the wrong type names its path.
        let e = read_edited(&["track", "shoe", "count"], json!([63, -1]));
        assert!(
            e.contains("track.shoe.count[1]") && e.contains("m113-edited.json"),
            "{e}"
        );
        // The data as shipped reads.
        assert!(TrackedVehicleData::from_json(M113_JSON, "data/m113.json").is_ok());
    }
}
