//! The constitutive laws, one file each.

pub mod kirchhoff_vol_dev;
pub mod mooney_rivlin;
pub mod neo_hookean;
pub mod saint_venant_kirchhoff;
