! The lines of a dpmpm_vars_<group>.inc list as statements keeping the values read in
! dest (a config_t, or one item of a repeatable group): a TEXT string longer than its
! component is a problem of group G (check_length). LOCAL variables are not kept here.
#undef VAR
#undef TEXT
#undef LOCAL
#define VAR(G, T, N, C, S, V) dest%C = N
#define TEXT(G, N, C, L, V, GS, NS) call check_length(pb, GS, NS, N, len(dest%C)); dest%C = N(1:len(dest%C))
#define LOCAL(G, T, N, S, V)
