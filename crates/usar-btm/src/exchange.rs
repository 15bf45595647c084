//! Exchanging BTMs: JSON (lossless; format `usar-btm`, version 1) and GraphML (for graph
//! tools such as yEd, Gephi or NetworkX; every attribute a `<data>` key).
//!
//! JSON readers ignore unknown top-level fields and keep unknown node kinds and `extra`
//! attributes, so a map written by a newer version still loads. Every map read is checked
//! ([`crate::validate`]): finite, sane measures, named kinds, links between existing nodes,
//! unique ids. GraphML is written only.

use crate::model::{Btm, Link, Node};
use crate::store::BtmError;
use serde::{Deserialize, Serialize};

pub const JSON_FORMAT: &str = "usar-btm";
pub const JSON_VERSION: u32 = 1;

#[derive(Serialize, Deserialize)]
struct JsonFile {
    format: String,
    version: u32,
    nodes: Vec<Node>,
    links: Vec<Link>,
}

/// Every node as JSON with Table I's derived fields added: its number of `links` and the
/// `link_angles_rad` between adjacent links (ignored on import).
pub fn node_rows(btm: &Btm) -> Vec<serde_json::Value> {
    btm.nodes
        .iter()
        .map(|n| {
            let mut v = serde_json::to_value(n).expect("nodes serialize");
            v["links"] = btm.links_of(n.id).count().into();
            v["link_angles_rad"] = btm.link_angles(n.id).into();
            v
        })
        .collect()
}

/// The map as the JSON exchange document (nodes as [`node_rows`]).
pub fn to_json_value(btm: &Btm) -> serde_json::Value {
    serde_json::json!({
        "format": JSON_FORMAT,
        "version": JSON_VERSION,
        "nodes": node_rows(btm),
        "links": btm.links,
    })
}

/// The map as pretty JSON (nodes as [`node_rows`]).
pub fn to_json(btm: &Btm) -> String {
    serde_json::to_string_pretty(&to_json_value(btm)).expect("JSON serializes")
}

/// Reads a map from JSON and checks it ([`crate::validate::check`]); `source` names it in
/// errors.
pub fn from_json(text: &str, source: &str) -> Result<Btm, BtmError> {
    let invalid = |what: String, message: String| BtmError::Invalid {
        path: source.to_string(),
        what,
        message,
    };
    let file: JsonFile = serde_json::from_str(text).map_err(|e| {
        let message = e.to_string();
        let message = message
            .rsplit_once(" at line ")
            .map_or(message.as_str(), |(m, _)| m)
            .to_string();
        invalid(format!("line {} column {}", e.line(), e.column()), message)
    })?;
    if file.format != JSON_FORMAT {
        return Err(invalid(
            "field `format`".into(),
            format!("found {:?}, expected \"{JSON_FORMAT}\"", file.format),
        ));
    }
    if file.version > JSON_VERSION {
        return Err(invalid(
            "field `version`".into(),
            format!("found {}, expected {JSON_VERSION} or older", file.version),
        ));
    }
    let btm = Btm {
        nodes: file.nodes,
        links: file.links,
    };
    crate::validate::check(&btm).map_err(|problem| BtmError::Check {
        path: source.to_string(),
        problem,
    })?;
    Ok(btm)
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The map as GraphML: one `<node>` per node and one `<edge>` per searched link; an
/// un-searched link becomes an edge to an open-end node `u<link id>` of kind `unknown`, which
/// stands for the unexplored far end (GraphML edges need two ends).
pub fn to_graphml(btm: &Btm) -> String {
    let node_keys = [
        ("x_m", "double"),
        ("y_m", "double"),
        ("kind", "string"),
        ("subtype", "string"),
        ("slope_inclination_rad", "double"),
        ("step_height_m", "double"),
        ("max_robot_inclination_rad", "double"),
        ("operator_note", "string"),
        ("extra", "string"),
    ];
    let edge_keys = [
        ("searched", "boolean"),
        ("direction_rad", "double"),
        ("length_m", "double"),
        ("min_width_m", "double"),
        ("max_inclination_rad", "double"),
        ("max_step_m", "double"),
        ("link_extra", "string"),
    ];
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\">\n",
    );
    for (k, t) in node_keys {
        out += &format!("  <key id=\"{k}\" for=\"node\" attr.name=\"{k}\" attr.type=\"{t}\"/>\n");
    }
    for (k, t) in edge_keys {
        out += &format!("  <key id=\"{k}\" for=\"edge\" attr.name=\"{k}\" attr.type=\"{t}\"/>\n");
    }
    out += "  <graph id=\"btm\" edgedefault=\"undirected\">\n";
    let data = |k: &str, v: Option<String>| {
        v.map(|v| format!("      <data key=\"{k}\">{}</data>\n", xml_escape(&v)))
            .unwrap_or_default()
    };
    let num = |v: Option<f64>| v.map(|v| v.to_string());
    for n in &btm.nodes {
        out += &format!("    <node id=\"n{}\">\n", n.id);
        out += &data("x_m", Some(n.x_m.to_string()));
        out += &data("y_m", Some(n.y_m.to_string()));
        out += &data("kind", Some(n.kind.clone()));
        out += &data("subtype", n.subtype.clone());
        out += &data("slope_inclination_rad", num(n.slope_inclination_rad));
        out += &data("step_height_m", num(n.step_height_m));
        out += &data(
            "max_robot_inclination_rad",
            num(n.max_robot_inclination_rad),
        );
        out += &data("operator_note", n.operator_note.clone());
        if !n.extra.is_empty() {
            out += &data("extra", serde_json::to_string(&n.extra).ok());
        }
        out += "    </node>\n";
    }
    for l in &btm.links {
        let target = match l.end {
            Some(e) => format!("n{e}"),
            None => {
                out += &format!(
                    "    <node id=\"u{}\">\n{}    </node>\n",
                    l.id,
                    data("kind", Some("unknown".into()))
                );
                format!("u{}", l.id)
            }
        };
        out += &format!(
            "    <edge id=\"l{}\" source=\"n{}\" target=\"{target}\">\n",
            l.id, l.start
        );
        out += &data("searched", Some(l.searched.to_string()));
        out += &data("direction_rad", Some(l.direction_rad.to_string()));
        out += &data("length_m", num(l.length_m));
        out += &data("min_width_m", num(l.min_width_m));
        out += &data("max_inclination_rad", num(l.max_inclination_rad));
        out += &data("max_step_m", num(l.max_step_m));
        if !l.extra.is_empty() {
            out += &data("link_extra", serde_json::to_string(&l.extra).ok());
        }
        out += "    </edge>\n";
    }
    out + "  </graph>\n</graphml>\n"
}

/// Reads a BTM from a `.json` file, a binary `.btmb` file ([`crate::wire`]) or a BTM database
/// (any other extension but `.graphml`, which is written only), and checks it
/// ([`crate::validate`]). Errors are one line naming the file.
pub fn read(path: &std::path::Path) -> Result<Btm, BtmError> {
    let ext = usar_world::io::extension(path);
    match ext.as_str() {
        "graphml" => {
            return Err(BtmError::Format {
                path: path.display().to_string(),
                message: "GraphML is an export format only, expected a .json, .btmb or BTM \
                          database (.sqlite) file"
                    .into(),
            });
        }
        // Read whole under the process's file-size limit (`usar --max-file-mb`), checked
        // before anything is read.
        "json" => {
            let text = usar_world::limits::read_text(path)?;
            return from_json(&text, &path.display().to_string());
        }
        "btmb" => {
            let bytes = usar_world::limits::read_file(path)?;
            return crate::wire::decode(&bytes).map_err(|problem| BtmError::Wire {
                path: path.display().to_string(),
                problem,
            });
        }
        _ => {}
    }
    crate::store::BtmStore::open(path).and_then(|s| s.load())
}

/// Writes a BTM as `.json`, `.graphml`, binary `.btmb` or a new BTM database (`.sqlite`),
/// atomically: the file appears complete or not at all.
pub fn write(btm: &Btm, path: &std::path::Path) -> Result<(), BtmError> {
    let ext = usar_world::io::extension(path);
    let text = match ext.as_str() {
        "json" => to_json(btm),
        "graphml" => to_graphml(btm),
        "btmb" => return Ok(usar_world::write_atomic(path, &crate::wire::encode(btm))?),
        "sqlite" | "db" => {
            let tmp = path.with_extension("sqlite.partial");
            let _ = std::fs::remove_file(&tmp);
            let mut store = crate::store::BtmStore::create(&tmp)?;
            store.put_all(btm)?;
            drop(store);
            return std::fs::rename(&tmp, path)
                .map_err(|io| usar_world::WorldError::io(path, io).into());
        }
        _ => {
            return Err(BtmError::Format {
                path: path.display().to_string(),
                message: format!(
                    "unknown BTM format {ext:?}, expected .json, .graphml, .btmb or .sqlite"
                ),
            });
        }
    };
    Ok(usar_world::write_atomic(path, text.as_bytes())?)
}
