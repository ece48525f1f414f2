//! The per-pixel hit record (the paper's hit buffer object, §4.3, plus what tools compare).

/// How many bounding spheres the pixel's ray pierced in its frame: the hardware record's
/// field (`rtl_model::units::hit_record`), one definition for both models.
pub use rtl_model::units::hit_record::SphereCount;

/// Instance id meaning "no instance".
pub const NO_INSTANCE: u16 = u16::MAX;

/// What a pixel gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitRecord {
    /// True if a voxel was hit.
    pub hit: bool,
    /// Spheres pierced in this frame (the paper's "nature of the hit").
    pub spheres: SphereCount,
    /// Instance hit, or [`NO_INSTANCE`].
    pub instance: u16,
    /// Ray parameter of the hit (world units, unit direction); +∞ on a miss.
    pub t: f64,
    /// Leaf coordinates in the instance's octree (0 on a miss).
    pub voxel: [u32; 3],
    /// Entry face normal in world space (0 on a miss).
    pub face_normal: [f32; 3],
    /// Leaf attribute normal in world space, for shading (0 on a miss).
    pub shade_normal: [f32; 3],
    /// Leaf colour RGBA8 (0 on a miss).
    pub colour: [u8; 4],
}

impl Default for HitRecord {
    fn default() -> Self {
        Self::MISS
    }
}

impl HitRecord {
    /// A ray that hit nothing (and pierced no sphere).
    pub const MISS: Self = Self {
        hit: false,
        spheres: SphereCount::None,
        instance: NO_INSTANCE,
        t: f64::INFINITY,
        voxel: [0; 3],
        face_normal: [0.0; 3],
        shade_normal: [0.0; 3],
        colour: [0; 4],
    };

    /// Bit-exact equality (t compared by bits), for the hit-buffer soundness checks.
    pub fn same_bits(&self, o: &Self) -> bool {
        self.hit == o.hit
            && self.spheres == o.spheres
            && self.instance == o.instance
            && self.t.to_bits() == o.t.to_bits()
            && self.voxel == o.voxel
            && self.face_normal.map(f32::to_bits) == o.face_normal.map(f32::to_bits)
            && self.shade_normal.map(f32::to_bits) == o.shade_normal.map(f32::to_bits)
            && self.colour == o.colour
    }
}
