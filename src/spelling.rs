//! The nearest valid name to a misspelled one, for messages that say what was meant
//! (`force_total` → `force_total_mg`).

/// The candidate nearest to `word` by edit distance (case-insensitive), if it is near enough to
/// be a slip: at most a third of the longer name's characters changed, or `word` a prefix of
/// it (a unit suffix left out).
pub(crate) fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let w = word.to_lowercase();
    candidates
        .into_iter()
        .map(|c| (distance(&w, &c.to_lowercase()), c))
        .filter(|(d, c)| {
            let longer = w.chars().count().max(c.chars().count());
            *d * 3 <= longer || (w.len() >= 3 && c.to_lowercase().starts_with(&w))
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// " (did you mean `X`?)" for the nearest candidate, or "".
pub(crate) fn suggestion<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    nearest(word, candidates).map_or(String::new(), |c| format!(" (did you mean `{c}`?)"))
}

/// Edit distance between `a` and `b` in characters, a swap of neighbours counting as one edit
/// (optimal string alignment: `widht` is one slip from `width`).
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for j in 0..=b.len() {
        d[0][j] = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distances() {
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("σ_app", "sigma_app"), 5);
        assert_eq!(distance("same", "same"), 0);
        assert_eq!(distance("widht", "width"), 1);
    }

    #[test]
    fn slips_find_their_name_and_other_words_none() {
        let cols = ["time", "force_total_mg", "force_lower_mg", "sigma_app", "height", "width"];
        assert_eq!(nearest("force_total", cols), Some("force_total_mg"));
        assert_eq!(nearest("force_totl_mg", cols), Some("force_total_mg"));
        assert_eq!(nearest("sigma_ap", cols), Some("sigma_app"));
        assert_eq!(nearest("Height", cols), Some("height"));
        assert_eq!(nearest("pressure", cols), None);
        assert_eq!(suggestion("widht", cols), " (did you mean `width`?)");
        assert_eq!(suggestion("xyz", cols), "");
    }
}
