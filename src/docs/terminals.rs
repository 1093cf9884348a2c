//! Terminals: the scene's physical ports, grouped from the structured variable names, and
//! `terminalsAndIcons/terminalsAndIcons.xml` (FMI 2.0.4, section 2.3 "Terminals and Icons":
//! the file "as defined in the FMI 3.0 Specification, 2.4.9", schema
//! `fmi3TerminalsAndIcons.xsd` and `fmi3Terminal.xsd`).
//!
//! A port is a prefix of structured names (`pulley1` in `pulley1.angle`) that has at least
//! one input: the master drives it (motion in, force out, or a load in). Prefixes with only
//! outputs are sensors (`tip.x` of a probe, `energy.*`) and no terminal.

use super::xml_text::escape;
use crate::variables::{Causality, VariableTable};

/// One variable of a terminal.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    /// The variable's full name, e.g. `pulley1.angle`.
    pub variable: String,
    /// Its name inside the terminal, e.g. `angle`.
    pub member: String,
    /// Input or output.
    pub causality: Causality,
}

/// A physical port of the scene.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Terminal {
    /// The common prefix, e.g. `pulley1`.
    pub name: String,
    /// Its inputs and outputs, in value-reference order.
    pub members: Vec<Member>,
}

impl Terminal {
    /// "in: angle, omega; out: torque, force_x, force_y".
    pub fn description(&self) -> String {
        let list = |c: Causality| {
            self.members
                .iter()
                .filter(|m| m.causality == c)
                .map(|m| m.member.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let (i, o) = (list(Causality::Input), list(Causality::Output));
        match (i.is_empty(), o.is_empty()) {
            (false, false) => format!("in: {i}; out: {o}"),
            (false, true) => format!("in: {i}"),
            _ => format!("out: {o}"),
        }
    }
}

/// The prefix of a structured name (everything before the last `.` outside brackets), or
/// `None` for a name without one.
pub fn prefix(name: &str) -> Option<(&str, &str)> {
    let mut depth = 0i32;
    let mut split = None;
    for (i, c) in name.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            '.' if depth == 0 => split = Some(i),
            _ => {}
        }
    }
    split.map(|i| (&name[..i], &name[i + 1..]))
}

/// The terminals of a variable table: inputs and outputs grouped by prefix, in the order
/// their first variable appears; groups without an input are left out.
pub fn terminals(vars: &VariableTable) -> Vec<Terminal> {
    let mut out: Vec<Terminal> = Vec::new();
    for v in vars.vars() {
        if v.causality == Causality::Parameter {
            continue;
        }
        let Some((p, m)) = prefix(&v.name) else {
            continue;
        };
        let member = Member {
            variable: v.name.clone(),
            member: m.to_string(),
            causality: v.causality,
        };
        match out.iter_mut().find(|t| t.name == p) {
            Some(t) => t.members.push(member),
            None => out.push(Terminal {
                name: p.to_string(),
                members: vec![member],
            }),
        }
    }
    out.retain(|t| t.members.iter().any(|m| m.causality == Causality::Input));
    out
}

/// `terminalsAndIcons.xml`: `fmiVersion` "3.0" (the schema's pattern requires 3.x), the
/// graphical representation of the icon (`model.png`) on a 200 × 200 coordinate system, and
/// one `Terminal` per port with `matchingRule` "bus" (members are matched by name and a
/// connected terminal may carry a subset, e.g. a position without its velocity) and every
/// member a causal `signal`.
pub fn terminals_and_icons_xml(terminals: &[Terminal]) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <fmiTerminalsAndIcons fmiVersion=\"3.0\">\n  <GraphicalRepresentation>\n    \
         <CoordinateSystem x1=\"-100\" y1=\"-100\" x2=\"100\" y2=\"100\" \
         suggestedScalingFactorTo_mm=\"0.1\"/>\n    \
         <Icon x1=\"-100\" y1=\"-100\" x2=\"100\" y2=\"100\"/>\n  </GraphicalRepresentation>\n",
    );
    if !terminals.is_empty() {
        s.push_str("  <Terminals>\n");
        for t in terminals {
            s.push_str(&format!(
                "    <Terminal name=\"{}\" matchingRule=\"bus\" description=\"{}\">\n",
                escape(&t.name),
                escape(&t.description())
            ));
            for m in &t.members {
                s.push_str(&format!(
                    "      <TerminalMemberVariable variableName=\"{}\" memberName=\"{}\" \
                     variableKind=\"signal\"/>\n",
                    escape(&m.variable),
                    escape(&m.member)
                ));
            }
            s.push_str("    </Terminal>\n");
        }
        s.push_str("  </Terminals>\n");
    }
    s.push_str("</fmiTerminalsAndIcons>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_split_at_the_last_dot_outside_brackets() {
        assert_eq!(prefix("pulley1.angle"), Some(("pulley1", "angle")));
        assert_eq!(prefix("belt.point[3].x"), Some(("belt.point[3]", "x")));
        assert_eq!(prefix("a.b[1.5]"), Some(("a", "b[1.5]")));
        assert_eq!(prefix("time"), None);
    }
}
