//! A crawler's words for the conditions of (P)'s certificate: its report on the crawler's
//! instance ([`super::general_report`]) names them so (`slip_stationarity` for (P)'s reaction
//! stationarity on a slipping block's face, `p + omega` for the switching function).

/// The crawler's name and statement of a condition of (P) (`theorem` "6.2", the discrete
/// group, or "2.2", the continuous one), where it has its own: blocks that slip, links' rates,
/// `p + omega` for (P)'s switching function `B^T p + omega` (`B^T p~ = p` on the instance).
pub(super) fn crawler_words(name: &str, theorem: &str) -> Option<(&'static str, &'static str)> {
    Some(match (theorem, name) {
        ("6.2", "adjoint") => (
            "adjoint",
            "adjoint equation and transversality: p_j - p_{j-1} = sum_f xi_{j,f} x*_f, p(T) = \
             p(0) (Thm 6.2 (px), (p2mx))",
        ),
        ("6.2", "complementarity") => (
            "complementarity",
            "xi_{j,f} (c_f - <x*_f, x_j>) = 0: dxi only where its face is active (Thm 6.1 (necd1))",
        ),
        ("6.2", "reaction_stationarity") => (
            "slip_stationarity",
            "<p_j, K nu_b> + lambda/N = 0 while block b slips; relaxed sign at biactive faces \
             (branch LP in D; Thm 6.2 (pr), eta in df1)",
        ),
        ("6.2", "branch_face_sign") => (
            "branch_face_sign",
            "xi_{j,f} <= 0 on an active face no slip holds (a true inequality of the branch LP)",
        ),
        ("6.2", "weak_maximality") => (
            "weak_maximality",
            "psi_j = -p_j - omega - lambda Df2(u_j) in N_U(u_j) (Thm 6.2 (pw))",
        ),
        ("6.2", "sign") => ("sign", "xi_{j,f} >= 0"),
        ("6.2", "duration_stationarity") => (
            "duration_stationarity",
            "H_j = sum_l a_l |psi_{j,l}| over the rates at their bound (psi_j's weight on the \
             box's active rows) + lambda (Df2(u_j).u_j - f2(u_j)) is the same on every phase \
             (phase LP stationary in the durations: the maximised Hamiltonian is constant); \
             residual (max H - min H)/2",
        ),
        ("2.2", "adjoint") => (
            "adjoint",
            "dp = sum_j x*_j dxi^j, p(T) = p(0) (Thm 2.2 adjoint, transversality)",
        ),
        ("2.2", "sign") => (
            "sign",
            "dxi^j >= 0 (Thm 2.2; Thm 6.1 for the paper's P_m, whose state constraints are pure \
             inequalities: the branch LP of the computational P_m leaves it free on held faces)",
        ),
        ("2.2", "weak_maximality") => (
            "weak_maximality",
            "int_0^T dist(psi(t), N_U(u(t))) dt, psi = -p - omega - lambda Df2(u) (Thm 2.2)",
        ),
        ("2.2", "nontriviality") => (
            "nontriviality",
            "lambda + ||p||_inf > 0, scaled to 1 (Thm 2.2)",
        ),
        ("2.2", "nondegeneracy") => (
            "nondegeneracy",
            "p_l(t) + omega_l != 0 for all t and l (§4 (nndg)): min |p + omega| above 1e-6 \
             max(sup|p + omega|, 1/(N k_max)) and the solver's resolution; residual 1 when it \
             is not (min |p + omega| is reported beside J); required unless f2 is strictly \
             convex and lambda > 0",
        ),
        ("2.2", "control_law") => (
            "control_law",
            "u = -a sign(p + omega) where p + omega != 0 (f2 = 0, §4), u = proj_U(-(p + \
             omega)/(lambda c)) (f2 = (c/2)|u|^2): max |u - law| / (2 a)",
        ),
        _ => return None,
    })
}
