//! The dense linear algebra of the panel solver: mirror symmetry of a mesh and the solves of
//! its influence system (by symmetric and antisymmetric halves where the mesh is symmetric,
//! else one LU with partial pivoting).

use super::from_faer;
use crate::panels::{Mesh, Panel};
use faer::complex_native::c64;
use faer::dyn_stack::{GlobalPodBuffer, PodStack};
use faer::reborrow::ReborrowMut;
use faer::{Conj, Mat, Parallelism};

/// Solves `matrix * x = rhs` for a matrix that commutes with the mirror permutation `m`
/// (`matrix[(m(i), m(p))] = matrix[(i, p)]`, an involution): in its symmetric and
/// antisymmetric halves. With `R` one index of every mirror pair (and the panels their own
/// image, which carry no antisymmetric part), `x = x_s + x_a`,
///
/// ```text
/// (S(i,p) + S(i,m(p))) x_s(p) = (b(i) + b(m(i)))/2,   x(m(i)) = x_s(i) - x_a(i),
/// (S(i,p) - S(i,m(p))) x_a(p) = (b(i) - b(m(i)))/2,   i, p in R,
/// ```
///
/// two systems of half the size: a quarter of the factorization. `None` when either breaks
/// down.
pub(super) fn solve_mirrored(matrix: &Mat<c64>, rhs: Mat<c64>, m: &[usize]) -> Option<Mat<c64>> {
    let n = matrix.nrows();
    let columns = rhs.ncols();
    let half: Vec<usize> = (0..n).filter(|&i| m[i] >= i).collect();
    let pairs: Vec<usize> = half.iter().copied().filter(|&i| m[i] > i).collect();
    let reduced = |rows: &[usize], sign: f64| {
        let mut s = Mat::<c64>::zeros(rows.len(), rows.len());
        for (c, &p) in rows.iter().enumerate() {
            for (r, &i) in rows.iter().enumerate() {
                let mut value = matrix.read(i, p);
                if m[p] != p {
                    let image = matrix.read(i, m[p]);
                    value = c64 {
                        re: value.re + sign * image.re,
                        im: value.im + sign * image.im,
                    };
                }
                s.write(r, c, value);
            }
        }
        let mut b = Mat::<c64>::zeros(rows.len(), columns);
        for j in 0..columns {
            for (r, &i) in rows.iter().enumerate() {
                let (own, image) = (rhs.read(i, j), rhs.read(m[i], j));
                b.write(
                    r,
                    j,
                    c64 {
                        re: 0.5 * (own.re + sign * image.re),
                        im: 0.5 * (own.im + sign * image.im),
                    },
                );
            }
        }
        (s, b)
    };
    let (s_sym, b_sym) = reduced(&half, 1.0);
    let x_sym = solve_dense(s_sym, b_sym)?;
    let x_anti = if pairs.is_empty() {
        Mat::<c64>::zeros(0, columns)
    } else {
        let (s_anti, b_anti) = reduced(&pairs, -1.0);
        solve_dense(s_anti, b_anti)?
    };
    let mut x = Mat::<c64>::zeros(n, columns);
    for j in 0..columns {
        let mut a = 0;
        for (r, &i) in half.iter().enumerate() {
            let s = x_sym.read(r, j);
            if m[i] == i {
                x.write(i, j, s);
            } else {
                let d = x_anti.read(a, j);
                a += 1;
                x.write(
                    i,
                    j,
                    c64 {
                        re: s.re + d.re,
                        im: s.im + d.im,
                    },
                );
                x.write(
                    m[i],
                    j,
                    c64 {
                        re: s.re - d.re,
                        im: s.im - d.im,
                    },
                );
            }
        }
    }
    Some(x)
}

/// Solves `matrix * x = rhs` by LU with partial pivoting, on the calling thread only (the
/// parallelism of a sweep is over frequencies). `None` when the factorization breaks down.
pub(super) fn solve_dense(mut matrix: Mat<c64>, mut rhs: Mat<c64>) -> Option<Mat<c64>> {
    use faer::linalg::lu::partial_pivoting::{compute, solve};
    let n = matrix.nrows();
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let parallelism = Parallelism::None;
    let params = Default::default();
    let factor_req = compute::lu_in_place_req::<usize, c64>(n, n, parallelism, params).ok()?;
    let solve_req = solve::solve_in_place_req::<usize, c64>(n, n, rhs.ncols(), parallelism).ok()?;
    let mut buffer = GlobalPodBuffer::new(factor_req.or(solve_req));
    let mut stack = PodStack::new(&mut buffer);
    let (_, row_perm) = compute::lu_in_place(
        matrix.as_mut(),
        &mut perm,
        &mut perm_inv,
        parallelism,
        stack.rb_mut(),
        params,
    );
    let smallest_pivot = (0..n)
        .map(|k| from_faer(matrix.read(k, k)).norm())
        .fold(f64::INFINITY, f64::min);
    let largest_pivot = (0..n)
        .map(|k| from_faer(matrix.read(k, k)).norm())
        .fold(0.0, f64::max);
    // Also catches NaN pivots.
    if smallest_pivot.is_nan() || smallest_pivot <= 1e-14 * largest_pivot {
        return None;
    }
    solve::solve_in_place(
        matrix.as_ref(),
        Conj::No,
        row_perm,
        rhs.as_mut(),
        parallelism,
        stack.rb_mut(),
    );
    Some(rhs)
}

/// For a mesh symmetric about x = 0 (all built-in hulls and symmetric hull files), the index
/// of each panel's mirror image (body and lid panels, in unknown order); `None` otherwise.
pub(super) fn mirror_map(mesh: &Mesh) -> Option<Vec<usize>> {
    let panels: Vec<&Panel> = mesh.body.iter().chain(&mesh.lid).collect();
    let scale = panels.iter().map(|p| p.length).fold(0.0, f64::max);
    let tolerance = 1e-9 * scale;
    let mut order: Vec<usize> = (0..panels.len()).collect();
    order.sort_by(|&a, &b| {
        let (pa, pb) = (panels[a].centre, panels[b].centre);
        pa[0].total_cmp(&pb[0]).then(pa[1].total_cmp(&pb[1]))
    });
    let mut map = vec![usize::MAX; panels.len()];
    for (p, panel) in panels.iter().enumerate() {
        let target = [-panel.centre[0], panel.centre[1]];
        let k = order.partition_point(|&q| panels[q].centre[0] < target[0] - tolerance);
        let found = order[k..]
            .iter()
            .take_while(|&&q| panels[q].centre[0] <= target[0] + tolerance)
            .find(|&&q| {
                (panels[q].centre[1] - target[1]).abs() <= tolerance
                    && (panels[q].length - panel.length).abs() <= tolerance
                    && (panels[q].normal[0] + panel.normal[0]).abs() <= 1e-9
                    && (panels[q].normal[1] - panel.normal[1]).abs() <= 1e-9
                    && (q < mesh.body.len()) == (p < mesh.body.len())
            })?;
        map[p] = *found;
    }
    Some(map)
}
