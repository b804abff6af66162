//! Muscle groups whose parameter may be off together (METHOD.md §8's "parameter group"): e.g.
//! every knee extensor's L_ts too long by one factor after a limb was scaled wrongly. Groups of
//! at least two estimated muscles: the extension agonists, the flexion agonists, all estimated
//! muscles, and the anatomical groups found by name (vasti `vas`, gastrocnemii `gas`,
//! hamstrings `bif`, `bflh`, `semimem`, `semiten`).

use super::trials::DynamometryData;

/// Name fragments of the anatomical groups.
const ANATOMICAL: [(&str, &[&str]); 3] = [("vasti", &["vas"]), ("gastrocnemii", &["gas"]), ("hamstrings", &["bif", "bflh", "semimem", "semiten"])];

/// (group name, indices into `estimated`) of every group with two or more members, without
/// repeating a member set.
pub(super) fn muscle_groups(data: &DynamometryData, estimated: &[String]) -> Vec<(String, Vec<usize>)> {
    let members = |names: &[String]| -> Vec<usize> { (0..estimated.len()).filter(|&e| names.contains(&estimated[e])).collect() };
    let by_fragment = |fragments: &[&str]| -> Vec<usize> { (0..estimated.len()).filter(|&e| fragments.iter().any(|f| estimated[e].contains(f))).collect() };
    let mut groups = vec![
        ("extension agonists".to_string(), members(&data.extension_agonists)),
        ("flexion agonists".to_string(), members(&data.flexion_agonists)),
        ("estimated muscles".to_string(), (0..estimated.len()).collect()),
    ];
    groups.extend(ANATOMICAL.iter().map(|(name, fragments)| (name.to_string(), by_fragment(fragments))));
    let mut kept: Vec<(String, Vec<usize>)> = Vec::new();
    for (name, group) in groups {
        if group.len() >= 2 && !kept.iter().any(|(_, other)| *other == group) {
            kept.push((name, group));
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tuning::functional::test_data::train01;
    use crate::tuning::functional::TrialOptions;

    #[test]
    fn gait2392_knee_muscles_form_six_groups() {
        let data = train01(&TrialOptions::default());
        let names: Vec<String> = data.estimated_muscles.clone();
        let groups = muscle_groups(&data, &names);
        let named: Vec<(&str, Vec<&str>)> = groups.iter().map(|(g, m)| (g.as_str(), m.iter().map(|&e| names[e].as_str()).collect())).collect();
        assert_eq!(
            named,
            [
                ("extension agonists", vec!["rect_fem_r", "vas_int_r", "vas_lat_r", "vas_med_r"]),
                ("flexion agonists", vec!["bifemlh_r", "lat_gas_r", "med_gas_r", "semimem_r"]),
                ("estimated muscles", names.iter().map(String::as_str).collect()),
                ("vasti", vec!["vas_int_r", "vas_lat_r", "vas_med_r"]),
                ("gastrocnemii", vec!["lat_gas_r", "med_gas_r"]),
                ("hamstrings", vec!["bifemlh_r", "semimem_r"]),
            ]
        );
    }
}
