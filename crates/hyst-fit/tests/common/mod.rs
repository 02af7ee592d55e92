//! Helpers shared by the hyst-fit integration tests.

/// `identify` as these tests call it: no progress output, never interrupted, no provenance.
pub fn identify(
    data: &hyst_fit::Dataset,
    request: &hyst_fit::identify::Request,
) -> Result<hyst_fit::identify::Identified, hyst_fit::FitError> {
    hyst_fit::identify::identify(
        data,
        request,
        &mut hyst_fit::lm::Silent,
        &|| false,
        hyst_model::Provenance::default(),
    )
}
