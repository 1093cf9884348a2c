//! Writing knob values into a scene file: `[table] key = value` set line by line, so that the
//! advised scene keeps the original's comments and layout.

use super::knobs::SceneKey;
use crate::variables::Value;

/// The TOML literal of `v` at `key` (a name from the key's table for keys written as names).
pub fn literal(key: &SceneKey, v: Value) -> Result<String, String> {
    Ok(match (v, key.names) {
        (Value::Integer(i), Some(names)) => {
            let (name, _) = names
                .iter()
                .find(|(_, c)| *c == i)
                .ok_or_else(|| format!("[{}] {}: no name for code {i}", key.table, key.key))?;
            format!("\"{name}\"")
        }
        (Value::Integer(i), None) => i.to_string(),
        (Value::Boolean(b), _) => b.to_string(),
        // `{:?}` keeps a decimal point or exponent, so the value stays a TOML float
        (Value::Real(x), _) => format!("{x:?}"),
    })
}

/// The header name of a line `[table]` (not `[[array]]`), comments and blanks stripped.
fn header(line: &str) -> Option<&str> {
    let l = line.split('#').next().unwrap_or("").trim();
    (l.starts_with('[') && !l.starts_with("[[") && l.ends_with(']'))
        .then(|| l[1..l.len() - 1].trim())
}

/// `text` with `[table] key = literal`: the key's line replaced (a trailing comment kept), or
/// the key added under the table's header, or the table appended.
pub fn set_key(text: &str, table: &str, key: &str, literal: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let start = lines.iter().position(|l| header(l) == Some(table));
    let Some(start) = start else {
        let mut out = text.trim_end().to_string();
        out.push_str(&format!("\n\n[{table}]\n{key} = {literal}\n"));
        return out;
    };
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].trim_start().starts_with('['))
        .unwrap_or(lines.len());
    let is_key = |l: &str| {
        let l = l.trim_start();
        l.strip_prefix(key)
            .is_some_and(|rest| rest.trim_start().starts_with('='))
    };
    match (start + 1..end).find(|&i| is_key(&lines[i])) {
        Some(i) => {
            let comment = lines[i]
                .find(" #")
                .map(|c| format!("  {}", lines[i][c..].trim_start()))
                .unwrap_or_default();
            lines[i] = format!("{key} = {literal}{comment}");
        }
        None => lines.insert(start + 1, format!("{key} = {literal}")),
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
}

/// `text` without the line `[table] key = ...` (unchanged when there is none).
pub fn remove_key(text: &str, table: &str, key: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let Some(start) = lines.iter().position(|l| header(l) == Some(table)) else {
        return text.to_string();
    };
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].trim_start().starts_with('['))
        .unwrap_or(lines.len());
    let mut out: Vec<&str> = Vec::with_capacity(lines.len());
    for (i, l) in lines.iter().enumerate() {
        let t = l.trim_start();
        let hit = i > start
            && i < end
            && t.strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='));
        if !hit {
            out.push(l);
        }
    }
    let mut s = out.join("\n");
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_inserts_and_appends() {
        let text = "[mesh]\nn_elements = 8  # eight\n\n[solver]\nmax_step = 1e-3\n[[probes]]\nname = \"tip\"\n";
        let a = set_key(text, "mesh", "n_elements", "16");
        assert!(a.contains("n_elements = 16  # eight"), "{a}");
        let b = set_key(&a, "solver", "tolerance", "0.001");
        assert!(
            b.contains("[solver]\ntolerance = 0.001\nmax_step = 1e-3"),
            "{b}"
        );
        let c = set_key(&b, "element", "type", "\"ancf_cable_2d\"");
        assert!(c.ends_with("[element]\ntype = \"ancf_cable_2d\"\n"), "{c}");
        let e = remove_key(&a, "mesh", "n_elements");
        assert!(e.starts_with("[mesh]\n\n[solver]"), "{e}");
        // a key of the same name in another table is left alone
        let d = set_key(text, "solver", "name", "\"x\"");
        assert!(d.contains("[[probes]]\nname = \"tip\""), "{d}");
    }
}
