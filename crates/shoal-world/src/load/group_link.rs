//! A vehicle group's link settings — `access`, `arq_retries`, `ack_timeout` — for every
//! modem of its model, said once (`[[vehicles]] access = "csma_ca"`, `arq_retries = 5`)
//! instead of in each modem — the preset's modems too. Each is put into every modem of the
//! merged model before the model is read, so that it is checked exactly as a modem's own is;
//! a problem found in it is then reported once, at the group's setting. A modem of the
//! group's `model` that sets the same setting as well is a conflict: a setting goes in one
//! place.

use super::validator::Validator;
use crate::error::{FieldPath, ProblemKind, Seg};

/// Puts the group's link `settings` (name, value) into every modem of the merged model
/// `base`; `model`: the group's own model table, `group`: the group's field path. Returns
/// false (with a problem) if a modem of `model` sets one of them itself.
pub(super) fn apply(
    base: &mut toml::Table,
    model: Option<&toml::Table>,
    settings: &[(&str, &toml::Value)],
    group: &FieldPath,
    v: &mut Validator<'_>,
) -> bool {
    let modems = model
        .and_then(|m| m.get("modems"))
        .and_then(toml::Value::as_array);
    let mut fine = true;
    for (key, _) in settings {
        let own = modems.and_then(|ms| {
            ms.iter()
                .position(|m| m.as_table().is_some_and(|t| t.contains_key(*key)))
        });
        if let Some(k) = own {
            v.push(
                ProblemKind::Invalid,
                &group.key("model").key("modems").index(k).key(key),
                format!(
                    "the group's `{key}` ({}) already sets every modem's: give it in one place",
                    group.key(key)
                ),
            );
            fine = false;
        }
    }
    if !fine {
        return false;
    }
    if let Some(toml::Value::Array(modems)) = base.get_mut("modems") {
        for m in modems {
            if let toml::Value::Table(t) = m {
                for (key, value) in settings {
                    t.insert((*key).into(), (*value).clone());
                }
            }
        }
    }
    true
}

/// The field `field` of a modem's link setting that the group gave (`given`: `access`,
/// `arq_retries` or `ack_timeout`; `<group>.model.modems[k].access…`) as the group's
/// (`<group>.access…`); `None` for any other field.
pub(super) fn to_group(field: &FieldPath, group: &FieldPath, given: &[&str]) -> Option<FieldPath> {
    let rest = field.0.strip_prefix(group.0.as_slice())?;
    match rest {
        [
            Seg::Key(m),
            Seg::Key(ms),
            Seg::Index(_),
            Seg::Key(a),
            tail @ ..,
        ] if m == "model" && ms == "modems" && given.contains(&a.as_str()) => {
            let mut p = group.key(a);
            p.0.extend(tail.iter().cloned());
            Some(p)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A modem's link setting that the group gave becomes the group's; other fields, and
    /// the settings the group did not give, stay as they are.
    #[test]
    fn a_modems_link_setting_becomes_the_groups_if_the_group_gave_it() {
        let g = FieldPath::root().key("vehicles").index(2);
        let given = ["access", "ack_timeout"];
        let at = |f: &str| to_group(&FieldPath::parse(f), &g, &given).map(|p| p.to_string());
        assert_eq!(
            at("vehicles[2].model.modems[3].access.p").as_deref(),
            Some("vehicles[2].access.p")
        );
        assert_eq!(
            at("vehicles[2].model.modems[0].access").as_deref(),
            Some("vehicles[2].access")
        );
        assert_eq!(
            at("vehicles[2].model.modems[1].ack_timeout").as_deref(),
            Some("vehicles[2].ack_timeout")
        );
        for other in [
            "vehicles[2].model.modems[0].led_power",
            "vehicles[2].model.modems[0].arq_retries",
            "vehicles[1].model.modems[0].access.p",
            "vehicles[2].access",
        ] {
            assert_eq!(at(other), None, "{other}");
        }
    }
}
