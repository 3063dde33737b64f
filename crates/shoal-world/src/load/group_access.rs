//! A vehicle group's `access`: the medium access of every modem of its model, said once
//! (`[[vehicles]] access = "csma_ca"`) instead of in each modem — the preset's modems too.
//! It is put into every modem of the merged model before the model is read, so that it is
//! checked exactly as a modem's own `access` is; a problem found in it is then reported once,
//! at the group's `access`. A modem of the group's `model` that sets its own `access` as well
//! is a conflict: the setting goes in one place.

use super::validator::Validator;
use crate::error::{FieldPath, ProblemKind, Seg};

/// Puts the group's `access` into every modem of the merged model `base`; `model`: the
/// group's own model table, `group`: the group's field path. Returns false (with a problem)
/// if a modem of `model` sets its own `access`.
pub(super) fn apply(
    base: &mut toml::Table,
    model: Option<&toml::Table>,
    access: &toml::Value,
    group: &FieldPath,
    v: &mut Validator<'_>,
) -> bool {
    let own = model
        .and_then(|m| m.get("modems"))
        .and_then(toml::Value::as_array)
        .and_then(|modems| {
            modems
                .iter()
                .position(|m| m.as_table().is_some_and(|t| t.contains_key("access")))
        });
    if let Some(k) = own {
        v.push(
            ProblemKind::Invalid,
            &group.key("model").key("modems").index(k).key("access"),
            format!(
                "the group's `access` ({}) already sets every modem's: give it in one place",
                group.key("access")
            ),
        );
        return false;
    }
    if let Some(toml::Value::Array(modems)) = base.get_mut("modems") {
        for m in modems {
            if let toml::Value::Table(t) = m {
                t.insert("access".into(), access.clone());
            }
        }
    }
    true
}

/// The field `field` of a modem's `access` (`<group>.model.modems[k].access…`) as the
/// group's (`<group>.access…`); `None` for any other field.
pub(super) fn to_group(field: &FieldPath, group: &FieldPath) -> Option<FieldPath> {
    let rest = field.0.strip_prefix(group.0.as_slice())?;
    match rest {
        [
            Seg::Key(m),
            Seg::Key(ms),
            Seg::Index(_),
            Seg::Key(a),
            tail @ ..,
        ] if m == "model" && ms == "modems" && a == "access" => {
            let mut p = group.key("access");
            p.0.extend(tail.iter().cloned());
            Some(p)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A modem's access field becomes the group's; other fields stay as they are.
    #[test]
    fn a_modems_access_field_becomes_the_groups() {
        let g = FieldPath::root().key("vehicles").index(2);
        let f = FieldPath::parse("vehicles[2].model.modems[3].access.p");
        assert_eq!(
            to_group(&f, &g).unwrap().to_string(),
            "vehicles[2].access.p"
        );
        let f = FieldPath::parse("vehicles[2].model.modems[0].access");
        assert_eq!(to_group(&f, &g).unwrap().to_string(), "vehicles[2].access");
        for other in [
            "vehicles[2].model.modems[0].led_power",
            "vehicles[1].model.modems[0].access.p",
            "vehicles[2].access",
        ] {
            assert_eq!(to_group(&FieldPath::parse(other), &g), None, "{other}");
        }
    }
}
