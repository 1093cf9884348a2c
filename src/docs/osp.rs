//! `<model_name>_OspModelDescription.xml`: the scene's ports as OSP variable groups for
//! libcosim (OSP Interface Specification, namespace
//! `https://open-simulation-platform.com/OspModelDescription/1.0.0`; libcosim looks for the
//! file next to the FMU under this name). Every port becomes a `Generic` group of its
//! variables: the typed groups of OSP-IS (Force, LinearVelocity, ...) require exact member
//! counts and units per group, which a port mixing forces and moments (`load.fx` … `load.mz`)
//! does not have.
//!
//! libcosim connects two `Generic` groups (`VariableGroupConnection` in
//! `OspSystemStructure.xml`) member by member in the order they are listed, each pair from
//! the output to the input. Members are therefore listed sorted by their name inside the
//! port (`fx`, `fy`, `vx`, `vy`, `x`, `y`), not by causality, so that a motion port and the
//! force port it drives (`boom`'s `tip` and `link`'s `pivot` in `ssp/boom_link/`) pair
//! position with position and force with force.

use super::terminals::Terminal;
use super::xml_text::escape;

/// The OSP model description with one `Generic` variable group per terminal.
pub fn osp_model_description(terminals: &[Terminal]) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<OspModelDescription \
         xmlns=\"https://open-simulation-platform.com/OspModelDescription/1.0.0\" \
         version=\"1.0\">\n  <VariableGroups>\n",
    );
    for t in terminals {
        s.push_str(&format!("    <Generic name=\"{}\">\n", escape(&t.name)));
        let mut members: Vec<_> = t.members.iter().collect();
        members.sort_by(|a, b| a.member.cmp(&b.member));
        for m in members {
            s.push_str(&format!(
                "      <Variable ref=\"{}\"/>\n",
                escape(&m.variable)
            ));
        }
        s.push_str("    </Generic>\n");
    }
    s.push_str("  </VariableGroups>\n</OspModelDescription>\n");
    s
}

/// The file name libcosim looks for next to `<model_name>.fmu`.
pub fn osp_file_name(model_name: &str) -> String {
    format!("{model_name}_OspModelDescription.xml")
}
