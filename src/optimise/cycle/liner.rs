//! The liners a cycle design weighs, by name: the plain liner, the best uniform texture and
//! the design (zoned or banded). Every report lists them in that order.

use serde::ser::{Serialize, SerializeSeq, Serializer};

/// A liner of a cycle report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Liner {
    Plain,
    /// The best texture over the whole liner.
    Uniform,
    /// A texture per zone of the engine file (`texture cycle`, `--quasi-steady`).
    Zoned,
    /// Textured bands next to the dead centres (`--bands`).
    Banded,
}

impl Liner {
    /// Its name in the reports.
    pub fn name(self) -> &'static str {
        match self {
            Liner::Plain => "plain liner",
            Liner::Uniform => "uniform best",
            Liner::Zoned => "zoned",
            Liner::Banded => "banded",
        }
    }
}

/// One value per liner of a report: the plain liner's, the uniform one's and the design's.
/// Written as a list in that order (a report's JSON lists them so).
#[derive(Clone, Debug, PartialEq)]
pub struct Trio<T> {
    pub plain: T,
    pub uniform: T,
    pub designed: T,
}

impl<T> Trio<T> {
    /// The three in the report's order.
    pub fn each(&self) -> [&T; 3] {
        [&self.plain, &self.uniform, &self.designed]
    }

    /// The three with the liners they belong to, the design being `design`.
    pub fn named(&self, design: Liner) -> [(Liner, &T); 3] {
        [
            (Liner::Plain, &self.plain),
            (Liner::Uniform, &self.uniform),
            (design, &self.designed),
        ]
    }

    pub fn as_ref(&self) -> Trio<&T> {
        Trio {
            plain: &self.plain,
            uniform: &self.uniform,
            designed: &self.designed,
        }
    }

    pub fn map<U>(self, mut f: impl FnMut(T) -> U) -> Trio<U> {
        Trio {
            plain: f(self.plain),
            uniform: f(self.uniform),
            designed: f(self.designed),
        }
    }
}

impl<T: Serialize> Serialize for Trio<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(3))?;
        for x in self.each() {
            seq.serialize_element(x)?;
        }
        seq.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trio_is_written_as_the_list_the_reports_held() {
        let t = Trio {
            plain: Some(1.5),
            uniform: None,
            designed: Some(2.0),
        };
        assert_eq!(serde_json::to_string(&t).unwrap(), "[1.5,null,2.0]");
        let names: Vec<&str> = t.named(Liner::Banded).iter().map(|x| x.0.name()).collect();
        assert_eq!(names, ["plain liner", "uniform best", "banded"]);
        assert_eq!(t.map(|x| x.is_some()).each(), [&true, &false, &true]);
    }
}
