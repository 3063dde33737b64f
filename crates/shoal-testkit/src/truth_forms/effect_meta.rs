//! The descriptive methods every truth form that is an effect shares.

/// The descriptive methods of an [`Effect`] that is a truth form: not fittable (no parameters;
/// the values live in the struct), named after its form, summarised and explained by its law.
macro_rules! truth_effect_meta {
    // A type that carries its name and law in fields `name` and `law`.
    (fields) => {
        fn name(&self) -> &'static str {
            self.name
        }
        fn summary(&self) -> &'static str {
            self.law
        }
        fn explanation(&self) -> &'static str {
            self.law
        }
        fn params(
            &self,
            _vehicle: &shoal_model::vehicle::VehicleParams,
        ) -> Vec<shoal_model::effects::ParamInfo> {
            Vec::new()
        }
    };
    ($name:expr, $law:expr) => {
        fn name(&self) -> &'static str {
            $name
        }
        fn summary(&self) -> &'static str {
            $law
        }
        fn explanation(&self) -> &'static str {
            $law
        }
        fn params(
            &self,
            _vehicle: &shoal_model::vehicle::VehicleParams,
        ) -> Vec<shoal_model::effects::ParamInfo> {
            Vec::new()
        }
    };
}
pub(crate) use truth_effect_meta;
