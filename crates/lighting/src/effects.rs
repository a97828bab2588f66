//! The [`Effects`] bit set: which terms of the illumination model a draw evaluates, and the
//! dispatch from runtime bits to the `const FX: u32` instantiations of the shading kernels.

use std::fmt;
use std::ops::{BitAnd, BitOr, BitOrAssign, Not};

/// A set of shading effects. Shading code is generic over `const FX: u32` (the bits), so a term
/// whose bit is absent is folded away at compile time and costs nothing.
///
/// Bits 0..8 are the lighting terms that `phosphor-lighting` evaluates; [`Effects::BUMP`] is
/// carried for the rasterizer (it perturbs the normal before shading) and ignored here.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Effects(u32);

impl Effects {
    /// The lecture notes' `I = Ia Ka` term (`ka * Ia`).
    pub const AMBIENT: Effects = Effects(1 << 0);
    /// Lambert's `Kd Il (N.L)`.
    pub const DIFFUSE: Effects = Effects(1 << 1);
    /// Phong's `Ks Il (V.R)^ns` (or Blinn's `(N.H)^ns`).
    pub const SPECULAR: Effects = Effects(1 << 2);
    /// The specular coefficient `W(theta)` varies with the angle of incidence (otherwise `W = 1`).
    pub const FRESNEL: Effects = Effects(1 << 3);
    /// Distance attenuation `f(d)` of positional lights (otherwise `f = 1`).
    pub const ATTENUATION: Effects = Effects(1 << 4);
    /// Spot lights are evaluated (otherwise they are skipped).
    pub const SPOT: Effects = Effects(1 << 5);
    /// Distributed (tube, rect) lights' point samples are evaluated (otherwise skipped).
    pub const DISTRIBUTED: Effects = Effects(1 << 6);
    /// The lecture notes' self-luminous term `I = Ka` (`Material::emission`).
    pub const EMISSION: Effects = Effects(1 << 7);
    /// Bump mapping (normal perturbation, done by the rasterizer; no term here).
    pub const BUMP: Effects = Effects(1 << 8);
    /// No effect: shading returns zero.
    pub const NONE: Effects = Effects(0);
    /// Every effect.
    pub const ALL: Effects = Effects((1 << 9) - 1);
    /// The bits that change what `phosphor-lighting` computes (all but [`Effects::BUMP`]).
    pub const LIGHTING: Effects = Effects(Self::ALL.0 & !Self::BUMP.0);

    /// Every named flag with its name, in bit order (for `Display` and planners).
    pub const NAMED: [(Effects, &'static str); 9] = [
        (Self::AMBIENT, "ambient"),
        (Self::DIFFUSE, "diffuse"),
        (Self::SPECULAR, "specular"),
        (Self::FRESNEL, "fresnel"),
        (Self::ATTENUATION, "attenuation"),
        (Self::SPOT, "spot"),
        (Self::DISTRIBUTED, "distributed"),
        (Self::BUMP, "bump"),
        (Self::EMISSION, "emission"),
    ];

    /// The raw bits (what `shade::<FX>` takes as `FX`).
    #[inline]
    #[must_use]
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// The set with exactly these bits, or `None` when a bit outside [`Effects::ALL`] is set.
    #[inline]
    #[must_use]
    pub const fn from_bits(bits: u32) -> Option<Effects> {
        if bits & !Self::ALL.0 == 0 {
            Some(Effects(bits))
        } else {
            None
        }
    }

    /// The set with these bits, unknown bits dropped.
    #[inline]
    #[must_use]
    pub const fn from_bits_truncate(bits: u32) -> Effects {
        Effects(bits & Self::ALL.0)
    }

    /// True when every effect of `other` is in `self`.
    #[inline]
    #[must_use]
    pub const fn contains(self, other: Effects) -> bool {
        self.0 & other.0 == other.0
    }

    /// True when no effect is set.
    #[inline]
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The effects in both sets (what a draw uses: material needs and light-set needs).
    #[inline]
    #[must_use]
    pub const fn intersection(self, other: Effects) -> Effects {
        Effects(self.0 & other.0)
    }

    /// The effects in either set.
    #[inline]
    #[must_use]
    pub const fn union(self, other: Effects) -> Effects {
        Effects(self.0 | other.0)
    }

    /// `self` without the effects of `other`.
    #[inline]
    #[must_use]
    pub const fn difference(self, other: Effects) -> Effects {
        Effects(self.0 & !other.0)
    }

    /// `self` with `other` added or removed.
    #[inline]
    #[must_use]
    pub const fn with(self, other: Effects, on: bool) -> Effects {
        if on {
            self.union(other)
        } else {
            self.difference(other)
        }
    }
}

/// Lighting levels a draw's effects are rounded up to by [`Effects::canonical`], cheapest
/// first. Each includes AMBIENT and EMISSION (they cost one multiply-add) from the second on.
pub const CANONICAL_LEVELS: [Effects; 8] = {
    const fn bits(list: &[Effects]) -> Effects {
        let mut acc = 0;
        let mut i = 0;
        while i < list.len() {
            acc |= list[i].0;
            i += 1;
        }
        Effects(acc)
    }
    use Effects as E;
    const BASE: [Effects; 2] = [E::AMBIENT, E::EMISSION];
    [
        E::NONE,
        bits(&BASE),
        bits(&[BASE[0], BASE[1], E::DIFFUSE]),
        bits(&[BASE[0], BASE[1], E::DIFFUSE, E::ATTENUATION]),
        bits(&[BASE[0], BASE[1], E::DIFFUSE, E::SPECULAR]),
        bits(&[BASE[0], BASE[1], E::DIFFUSE, E::SPECULAR, E::ATTENUATION]),
        bits(&[
            BASE[0],
            BASE[1],
            E::DIFFUSE,
            E::SPECULAR,
            E::FRESNEL,
            E::ATTENUATION,
        ]),
        E::LIGHTING,
    ]
};

/// The bits of the 16 canonical sets: [`CANONICAL_LEVELS`], then the same with
/// [`Effects::BUMP`]; index with [`Effects::canonical_index`].
pub const CANONICAL_BITS: [u32; 16] = {
    let mut out = [0; 16];
    let mut i = 0;
    while i < 8 {
        out[i] = CANONICAL_LEVELS[i].0;
        out[i + 8] = CANONICAL_LEVELS[i].0 | Effects::BUMP.0;
        i += 1;
    }
    out
};

impl Effects {
    /// Index into [`CANONICAL_BITS`] of the cheapest canonical set containing `self`.
    #[must_use]
    pub const fn canonical_index(self) -> usize {
        let lighting = self.0 & Self::LIGHTING.0;
        let mut level = 0;
        while level < CANONICAL_LEVELS.len() - 1 && lighting & !CANONICAL_LEVELS[level].0 != 0 {
            level += 1;
        }
        if self.0 & Self::BUMP.0 != 0 {
            level + 8
        } else {
            level
        }
    }

    /// The cheapest canonical superset of `self` (BUMP kept as is). Shading with a superset of
    /// what the inputs need gives the same result (the absent-term equivalence), so a
    /// rasterizer can instantiate its kernels for these 16 sets only instead of 512, at the
    /// price of evaluating a few terms whose coefficients are zero.
    #[must_use]
    pub const fn canonical(self) -> Effects {
        Effects(CANONICAL_BITS[self.canonical_index()])
    }
}

impl BitOr for Effects {
    type Output = Effects;
    fn bitor(self, rhs: Effects) -> Effects {
        self.union(rhs)
    }
}

impl BitOrAssign for Effects {
    fn bitor_assign(&mut self, rhs: Effects) {
        *self = self.union(rhs);
    }
}

impl BitAnd for Effects {
    type Output = Effects;
    fn bitand(self, rhs: Effects) -> Effects {
        self.intersection(rhs)
    }
}

impl Not for Effects {
    type Output = Effects;
    fn not(self) -> Effects {
        Effects(!self.0 & Self::ALL.0)
    }
}

/// Lists the flags joined by `+` (`ambient+diffuse`), or `none`.
impl fmt::Display for Effects {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            return f.write_str("none");
        }
        let mut first = true;
        for (flag, name) in Self::NAMED {
            if self.contains(flag) {
                if !first {
                    f.write_str("+")?;
                }
                f.write_str(name)?;
                first = false;
            }
        }
        Ok(())
    }
}

impl fmt::Debug for Effects {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Effects({self})")
    }
}

/// Runs `$body` with `$fx` bound to a `const u32` equal to the runtime `$effects` bits, so that
/// generic kernels (`shade::<FX>`, a rasterizer's span loop) are monomorphized for every one of
/// the 512 subsets of [`Effects::ALL`]. Unknown bits are dropped.
///
/// ```
/// use phosphor_lighting::{dispatch_effects, Effects};
/// fn count<const FX: u32>() -> u32 { FX.count_ones() }
/// let fx = Effects::AMBIENT | Effects::DIFFUSE;
/// assert_eq!(dispatch_effects!(fx, FX => count::<FX>()), 2);
/// ```
#[macro_export]
macro_rules! dispatch_effects {
    ($effects:expr, $fx:ident => $body:expr) => {
        $crate::__dispatch_effects_arms!($effects, $fx, $body, [0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32 33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 49 50 51 52 53 54 55 56 57 58 59 60 61 62 63 64 65 66 67 68 69 70 71 72 73 74 75 76 77 78 79 80 81 82 83 84 85 86 87 88 89 90 91 92 93 94 95 96 97 98 99 100 101 102 103 104 105 106 107 108 109 110 111 112 113 114 115 116 117 118 119 120 121 122 123 124 125 126 127 128 129 130 131 132 133 134 135 136 137 138 139 140 141 142 143 144 145 146 147 148 149 150 151 152 153 154 155 156 157 158 159 160 161 162 163 164 165 166 167 168 169 170 171 172 173 174 175 176 177 178 179 180 181 182 183 184 185 186 187 188 189 190 191 192 193 194 195 196 197 198 199 200 201 202 203 204 205 206 207 208 209 210 211 212 213 214 215 216 217 218 219 220 221 222 223 224 225 226 227 228 229 230 231 232 233 234 235 236 237 238 239 240 241 242 243 244 245 246 247 248 249 250 251 252 253 254 255 256 257 258 259 260 261 262 263 264 265 266 267 268 269 270 271 272 273 274 275 276 277 278 279 280 281 282 283 284 285 286 287 288 289 290 291 292 293 294 295 296 297 298 299 300 301 302 303 304 305 306 307 308 309 310 311 312 313 314 315 316 317 318 319 320 321 322 323 324 325 326 327 328 329 330 331 332 333 334 335 336 337 338 339 340 341 342 343 344 345 346 347 348 349 350 351 352 353 354 355 356 357 358 359 360 361 362 363 364 365 366 367 368 369 370 371 372 373 374 375 376 377 378 379 380 381 382 383 384 385 386 387 388 389 390 391 392 393 394 395 396 397 398 399 400 401 402 403 404 405 406 407 408 409 410 411 412 413 414 415 416 417 418 419 420 421 422 423 424 425 426 427 428 429 430 431 432 433 434 435 436 437 438 439 440 441 442 443 444 445 446 447 448 449 450 451 452 453 454 455 456 457 458 459 460 461 462 463 464 465 466 467 468 469 470 471 472 473 474 475 476 477 478 479 480 481 482 483 484 485 486 487 488 489 490 491 492 493 494 495 496 497 498 499 500 501 502 503 504 505 506 507 508 509 510 511])
    };
}

/// Like [`dispatch_effects!`] but binds `$fx` to [`Effects::canonical`] of the runtime bits:
/// 16 instantiations instead of 512, same results (see [`Effects::canonical`]).
///
/// ```
/// use phosphor_lighting::{dispatch_canonical_effects, Effects};
/// fn bits<const FX: u32>() -> u32 { FX }
/// let fx = Effects::DIFFUSE;
/// let canonical = dispatch_canonical_effects!(fx, FX => bits::<FX>());
/// assert_eq!(canonical, (Effects::AMBIENT | Effects::EMISSION | Effects::DIFFUSE).bits());
/// ```
#[macro_export]
macro_rules! dispatch_canonical_effects {
    ($effects:expr, $fx:ident => $body:expr) => {
        $crate::__dispatch_canonical_arms!(
            $effects, $fx, $body, [0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15]
        )
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __dispatch_canonical_arms {
    ($effects:expr, $fx:ident, $body:expr, [$($n:literal)*]) => {
        match $crate::Effects::canonical_index($effects) {
            $( $n => {
                #[allow(non_upper_case_globals)]
                const $fx: u32 = $crate::effects::CANONICAL_BITS[$n];
                $body
            } )*
            _ => {
                #[allow(non_upper_case_globals)]
                const $fx: u32 = $crate::Effects::ALL.bits();
                $body
            }
        }
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __dispatch_effects_arms {
    ($effects:expr, $fx:ident, $body:expr, [$($n:literal)*]) => {
        match $crate::Effects::bits($effects) & $crate::Effects::ALL.bits() {
            $( $n => {
                #[allow(non_upper_case_globals)]
                const $fx: u32 = $n;
                $body
            } )*
            _ => {
                #[allow(non_upper_case_globals)]
                const $fx: u32 = $crate::Effects::ALL.bits();
                $body
            }
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_are_distinct_bits_covering_all() {
        let mut acc = 0;
        for (flag, _) in Effects::NAMED {
            assert_eq!(flag.bits().count_ones(), 1);
            assert_eq!(acc & flag.bits(), 0);
            acc |= flag.bits();
        }
        assert_eq!(acc, Effects::ALL.bits());
    }

    #[test]
    fn set_operations_behave_like_bit_sets() {
        let a = Effects::AMBIENT | Effects::DIFFUSE;
        assert!(a.contains(Effects::DIFFUSE));
        assert!(!a.contains(Effects::SPECULAR));
        assert_eq!(a & Effects::DIFFUSE, Effects::DIFFUSE);
        assert_eq!((!a).intersection(a), Effects::NONE);
        assert_eq!(Effects::from_bits(1 << 20), None);
        assert_eq!(Effects::from_bits_truncate(a.bits() | 1 << 20), a);
        assert_eq!(a.to_string(), "ambient+diffuse");
        assert_eq!(Effects::NONE.to_string(), "none");
    }

    #[test]
    fn canonical_sets_are_the_cheapest_listed_supersets() {
        for bits in 0..512 {
            let fx = Effects::from_bits_truncate(bits);
            let c = fx.canonical();
            assert!(c.contains(fx), "{fx} -> {c}");
            assert_eq!(c.contains(Effects::BUMP), fx.contains(Effects::BUMP));
            let level = fx.canonical_index() % 8;
            for cheaper in &CANONICAL_LEVELS[..level] {
                assert!(!cheaper.contains(fx.intersection(Effects::LIGHTING)));
            }
        }
        assert_eq!(Effects::NONE.canonical(), Effects::NONE);
        assert_eq!(Effects::ALL.canonical(), Effects::ALL);
    }

    #[test]
    fn dispatch_binds_the_runtime_bits_as_a_const() {
        fn id<const FX: u32>() -> u32 {
            FX
        }
        for bits in 0..512 {
            let fx = Effects::from_bits_truncate(bits);
            assert_eq!(dispatch_effects!(fx, FX => id::<FX>()), bits);
        }
    }
}
