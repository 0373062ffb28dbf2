//! The physical case of one evaluation: the ring, the liner texture and the operating point
//! (docs/model.md §1–4, §7), with the validity rules of docs/model.md §2 checked up front.
//! Errors name the case's fields (`R`, `l1`, `per`, …): the command line and study files
//! translate them into their own flag or key names.

use serde::{Deserialize, Serialize};
use std::sync::Arc;

use super::asperity::{Asperity, ContactLaw};
use super::film::Boundary;
use super::flow_factors::FlowFactors;
use super::geometry::{CircularArc, Contact, HalfEllipsoid, Liner};
pub use super::input::{bad, one_line, short, InputError, Waiver};
use super::scales::Scales;

/// A lattice of half-ellipsoidal pockets (docs/model.md §2). Lengths in cm, depth in µm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Texture {
    /// Pocket semiaxis along the sliding direction x1 (cm).
    pub l1: f64,
    /// Pocket semiaxis across the sliding direction (cm).
    pub l2: f64,
    /// Lattice period along x1 (cm).
    pub per: f64,
    /// Lattice period along x2 (cm).
    pub width: f64,
    /// Pocket depth (µm).
    pub depth: f64,
    /// x1 of a pocket centre at t = 0 (cm): the texture's initial phase.
    #[serde(default)]
    pub phase: f64,
}

impl Texture {
    /// The texture in a table's words: the four lengths in cm to 1 µm (4 decimals), the
    /// depth to 0.1 µm.
    pub fn rounded_label(&self) -> String {
        format!(
            "l1={:.4} l2={:.4} per={:.4} width={:.4} depth={:.1}",
            self.l1, self.l2, self.per, self.width, self.depth
        )
    }

    /// Square lattice of circular pockets (the paper's family): l2 = l1, width = per.
    pub fn circular(l1: f64, per: f64, depth: f64) -> Self {
        Texture {
            l1,
            l2: l1,
            per,
            width: per,
            depth,
            phase: 0.0,
        }
    }
    /// The liner this texture makes, a pocket centre at `origin_cm` plus the texture's phase
    /// (docs/model.md §2).
    pub fn liner(&self, origin_cm: f64) -> Liner {
        Liner {
            pocket: Some(Arc::new(HalfEllipsoid {
                l1_cm: self.l1,
                l2_cm: self.l2,
                depth_um: self.depth,
            })),
            per_cm: self.per,
            width_cm: self.width,
            // The phase within one period: a phase of 1e15 cm would leave no digits for the
            // pocket's position (the texture repeats every `per`).
            phase_cm: (origin_cm + self.phase).rem_euclid(self.per),
        }
    }

    /// Textured area fraction π·l1·l2/(per·width).
    pub fn area_fraction(&self) -> f64 {
        std::f64::consts::PI * self.l1 * self.l2 / (self.per * self.width)
    }
}

/// One physical case. Defaults are the paper's operating point (docs/model.md §1–4, §7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseSpec {
    /// Ring face radius R (cm); f64::INFINITY for a flat ring (written "inf").
    #[serde(rename = "R", with = "radius")]
    pub r: f64,
    /// None: untextured liner.
    pub texture: Option<Texture>,
    /// Liner speed u (units of U = 10 m/s).
    pub u: f64,
    /// Ring pre-stress load per unit width W_ps (units of 2.4e7 N/m).
    pub w_ps: f64,
    /// Ring mass per unit width m (units of 2.4e7 kg/m).
    pub mass: f64,
    /// Inlet oil film thickness (µm).
    pub d_oil: f64,
    /// Shear threshold θ_s of the Couette switch (eq. 9).
    pub theta_s: f64,
    /// Gap outside the ring e (µm).
    pub e: f64,
    /// Initial ring position Z(0) (µm) and velocity Z'(0).
    pub z0: f64,
    pub v0: f64,
    /// Axial width of the ring face b − a (cm; the paper's ring: 0.08). Left out of the
    /// serialised case (and so of cache keys) at the paper's width.
    #[serde(
        default = "paper_ring_width",
        skip_serializing_if = "is_paper_ring_width"
    )]
    pub ring_width: f64,
    /// Asperity contact between ring face and liner plateau (docs/model.md §11), its
    /// constants in SI; None: the film alone carries the ring. Left out of the serialised
    /// case (and so of cache keys) at the defaults.
    #[serde(
        default = "default_contact",
        skip_serializing_if = "is_default_contact"
    )]
    pub contact: Option<Asperity>,
    /// The run's scales U and μ (docs/model.md §1): the scaled film and ring do not depend on
    /// them, the contact's pressure and shear in scaled units do, through μU. Serialised (so
    /// in cache keys) unless they are the paper's: two points of equal W_ps and m but
    /// different μU are one scaled film but not one contact (docs/model.md §11).
    #[serde(default = "paper_scales", skip_serializing_if = "is_paper_scales")]
    pub scales: Scales,
    /// The rough film's flow factors (docs/model.md §11, "Flow factors"); None: the film of
    /// smooth surfaces, the paper's. Left out of the serialised case (and so of cache keys)
    /// when None.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flow: Option<FlowFactors>,
}

fn default_contact() -> Option<Asperity> {
    Some(Asperity::default())
}

fn is_default_contact(c: &Option<Asperity>) -> bool {
    *c == default_contact()
}

fn paper_scales() -> Scales {
    Scales::PAPER
}

fn is_paper_scales(s: &Scales) -> bool {
    *s == Scales::PAPER
}

/// The paper's ring width (cm, docs/model.md §2).
pub const PAPER_RING_WIDTH: f64 = 0.08;

fn paper_ring_width() -> f64 {
    PAPER_RING_WIDTH
}

fn is_paper_ring_width(w: &f64) -> bool {
    *w == PAPER_RING_WIDTH
}

impl CaseSpec {
    /// The film's boundary data (docs/model.md §3): p = 0 at both ends, the oil supply d_oil
    /// carried in at x1 = 0 by the liner's speed.
    pub fn film_boundary(&self) -> Boundary {
        Boundary {
            u: self.u,
            u_rough: self.u,
            p_left: 0.0,
            p_right: 0.0,
            phi_inlet: self.d_oil,
            cavity_left: 0.0,
            cavity_right: 0.0,
        }
    }

    /// The paper's operating point for a ring of radius R, untextured liner.
    pub fn paper(r: f64) -> Self {
        CaseSpec {
            r,
            texture: None,
            u: 1.0,
            w_ps: 1.66e-6,
            mass: 2.0e-9,
            d_oil: 20.0,
            theta_s: 0.95,
            e: 1000.0,
            z0: 2.5,
            v0: 0.0,
            ring_width: PAPER_RING_WIDTH,
            contact: default_contact(),
            scales: Scales::PAPER,
            flow: None,
        }
    }

    /// The asperity contact of this case in its scaled units (docs/model.md §11), None
    /// without contact.
    pub fn contact_law(&self) -> Option<ContactLaw> {
        self.contact.map(|a| ContactLaw::new(&a, &self.scales))
    }
    pub fn with_texture(mut self, t: Texture) -> Self {
        self.texture = Some(t);
        self
    }

    /// The contact geometry (docs/model.md §2): the paper's layout scaled to the ring width.
    pub fn contact(&self) -> Contact {
        let liner = self
            .texture
            .as_ref()
            .map_or_else(Liner::smooth, |t| t.liner(0.0));
        let mut c = Contact::paper(Arc::new(CircularArc { radius_cm: self.r }), liner);
        c.e_um = self.e;
        c.with_ring_width(self.ring_width)
    }

    /// Short label for messages, e.g. "R=0.8 l1=0.01 l2=0.01 per=0.06 width=0.06 depth=5".
    pub fn label(&self) -> String {
        // `short` is the plain form for every everyday value, and keeps absurd ones short.
        let mut s = format!("R={}", short(self.r));
        if let Some(t) = &self.texture {
            s += &format!(
                " l1={} l2={} per={} width={} depth={}",
                short(t.l1),
                short(t.l2),
                short(t.per),
                short(t.width),
                short(t.depth)
            );
            if t.phase != 0.0 {
                s += &format!(" phase={}", short(t.phase));
            }
        } else {
            s += " untextured";
        }
        // The operating point where it is not the paper's.
        let paper = CaseSpec::paper(self.r);
        for (name, v, p) in [
            ("u", self.u, paper.u),
            ("w_ps", self.w_ps, paper.w_ps),
            ("mass", self.mass, paper.mass),
            ("d_oil", self.d_oil, paper.d_oil),
            ("ring_width", self.ring_width, paper.ring_width),
        ] {
            if v != p {
                s += &format!(" {name}={}", short(v));
            }
        }
        s
    }
}

/// `v` must be finite and positive.
pub fn positive(param: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(param, v, "must be a finite number > 0"))
    }
}

/// Whether a ring face of radius `r_cm` spans a ring of half width `half_width_cm`: R must
/// exceed it (docs/model.md §2; a flat ring's R is ∞, a NaN never does).
pub fn face_spans_ring(r_cm: f64, half_width_cm: f64) -> bool {
    r_cm > half_width_cm
}

/// Narrowest and widest ring faces accepted (cm): 0.1 to 10 mm, beyond any compression or
/// oil-control ring (a typo in the unit, not a ring).
pub const RING_WIDTH_RANGE: (f64, f64) = (0.01, 1.0);

impl CaseSpec {
    /// Checks docs/model.md §2's rules. `allow_thick` lifts the thin-film rule
    /// 10⁴·l ≥ 5·depth.
    pub fn validate(&self, allow_thick: bool) -> Result<(), InputError> {
        let (w_lo, w_hi) = RING_WIDTH_RANGE;
        if !(self.ring_width.is_finite() && (w_lo..=w_hi).contains(&self.ring_width)) {
            return Err(bad(
                "ring_width",
                self.ring_width,
                format!("the ring width must lie in [{w_lo}, {w_hi}] cm (0.1 to 10 mm)"),
            ));
        }
        let half = 0.5 * self.ring_width;
        if !face_spans_ring(self.r, half) {
            return Err(bad(
                "R",
                self.r,
                format!(
                    "the ring face radius must exceed half the ring width ({} cm); use inf for a flat ring",
                    short(half)
                ),
            ));
        }
        positive("u", self.u)?;
        positive("w_ps", self.w_ps)?;
        positive("mass", self.mass)?;
        positive("d_oil", self.d_oil)?;
        positive("e", self.e)?;
        positive("z0", self.z0)?;
        if !self.v0.is_finite() {
            return Err(bad("v0", self.v0, "must be finite"));
        }
        if !(self.theta_s.is_finite() && (0.0..1.0).contains(&self.theta_s)) {
            return Err(bad("theta_s", self.theta_s, "must lie in [0, 1)"));
        }
        if let Some(a) = &self.contact {
            a.check()?;
        }
        if let Some(t) = &self.texture {
            positive("l1", t.l1)?;
            positive("l2", t.l2)?;
            positive("per", t.per)?;
            positive("width", t.width)?;
            positive("depth", t.depth)?;
            if !t.phase.is_finite() {
                return Err(bad("phase", t.phase, "must be finite"));
            }
            if 2.0 * t.l1 > t.per * (1.0 + 1e-12) {
                return Err(bad(
                    "l1",
                    t.l1,
                    format!(
                        "2·l1 must not exceed per = {} (pockets would overlap)",
                        t.per
                    ),
                ));
            }
            if 2.0 * t.l2 > t.width * (1.0 + 1e-12) {
                return Err(bad(
                    "l2",
                    t.l2,
                    format!(
                        "2·l2 must not exceed width = {} (pockets would overlap)",
                        t.width
                    ),
                ));
            }
            if !allow_thick {
                for (name, l) in [("l1", t.l1), ("l2", t.l2)] {
                    if 1e4 * l < 5.0 * t.depth * (1.0 - 1e-12) {
                        return Err(InputError {
                            waiver: Some(Waiver::ThickPockets),
                            ..bad(
                                name,
                                l,
                                format!(
                                    "thin-film validity needs 10⁴·l ≥ 5·depth (depth = {} µm needs l ≥ {} cm)",
                                    t.depth,
                                    5.0 * t.depth * 1e-4
                                ),
                            )
                        });
                    }
                }
            }
        }
        Ok(())
    }
}

/// Serialises R with "inf" for a flat ring (JSON has no infinity).
mod radius {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(r: &f64, s: S) -> Result<S::Ok, S::Error> {
        if r.is_infinite() {
            s.serialize_str("inf")
        } else {
            s.serialize_f64(*r)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum R {
            Num(f64),
            Text(String),
        }
        match R::deserialize(d)? {
            R::Num(v) => Ok(v),
            R::Text(t) if t == "inf" => Ok(f64::INFINITY),
            R::Text(t) => Err(serde::de::Error::custom(format!(
                "R must be a number of cm or \"inf\", not {t:?}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn file_messages_are_one_line_with_numbers_short() {
        let big = format!(
            "invalid type: floating point `{}`, expected usize\n  |\n",
            "1".to_string() + &"0".repeat(300) + ".0"
        );
        assert_eq!(
            one_line(&big),
            "invalid type: floating point `1e300`, expected usize |"
        );
        assert_eq!(
            one_line("line 3, column 7: 0.5 and 12.25"),
            "line 3, column 7: 0.5 and 12.25"
        );
    }

    use super::*;

    #[test]
    fn flat_ring_round_trips_through_json() {
        let c = CaseSpec::paper(f64::INFINITY);
        let s = serde_json::to_string(&c).unwrap();
        assert!(s.contains("\"R\":\"inf\""));
        let back: CaseSpec = serde_json::from_str(&s).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn rules_of_docs_model_md_section_2() {
        let ok = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
        assert!(ok.validate(false).is_ok());
        let overlap = CaseSpec::paper(0.8).with_texture(Texture::circular(0.04, 0.06, 5.0));
        assert_eq!(overlap.validate(false).unwrap_err().param, "l1");
        let thick = CaseSpec::paper(0.8).with_texture(Texture::circular(0.005, 0.06, 20.0));
        let e = thick.validate(false).unwrap_err();
        assert_eq!(
            (e.param.as_str(), e.waiver),
            ("l1", Some(Waiver::ThickPockets))
        );
        assert!(thick.validate(true).is_ok());
        assert_eq!(
            CaseSpec::paper(0.03).validate(false).unwrap_err().param,
            "R"
        );
    }
}
