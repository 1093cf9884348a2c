//! SSP parameter sets (`.ssv`, MIME type `application/x-ssp-parameter-set`): SSP 1.0,
//! "System Structure Parameter Values" (root `ssv:ParameterSet` with `version` and `name`,
//! `ssv:Parameters` of `ssv:Parameter name=...` each holding one `ssv:Real`, `ssv:Integer` or
//! `ssv:Boolean` with a `value`), the schema fmpy ships as
//! `fmpy/ssp/schema/SystemStructureParameterValues.xsd`. FMI-LS-REF section "Role parameter":
//! the set is applied as if bound without prefix, i.e. to the FMU variables of the same name.

use crate::docs::xml_text::escape;
use crate::variables::Value;

/// SSV namespace of SSP 1.0.
pub const SSV_NAMESPACE: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";

/// The `.ssv` text of the parameter set `name` (`description` for users) with `values`
/// (variable name, value) in the given order.
pub fn parameter_set(name: &str, description: &str, values: &[(&str, Value)]) -> String {
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <ssv:ParameterSet xmlns:ssv=\"{SSV_NAMESPACE}\" version=\"1.0\" name=\"{}\" \
         description=\"{}\">\n  <ssv:Parameters>\n",
        escape(name),
        escape(description)
    );
    for (n, v) in values {
        let (ty, text) = match v {
            Value::Real(x) => ("Real", format!("{x:e}")),
            Value::Integer(i) => ("Integer", i.to_string()),
            Value::Boolean(b) => ("Boolean", b.to_string()),
        };
        s.push_str(&format!(
            "    <ssv:Parameter name=\"{}\">\n      <ssv:{ty} value=\"{text}\"/>\n    </ssv:Parameter>\n",
            escape(n)
        ));
    }
    s.push_str("  </ssv:Parameters>\n</ssv:ParameterSet>\n");
    s
}
