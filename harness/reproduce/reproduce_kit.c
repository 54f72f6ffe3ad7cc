/* reproduce_kit.c: the machinery every `reproduce` experiment shares
 * (reproduce_kit.h): options, the output folder and CSV, scenes and their
 * stand-ins, measurements made once and reused, the report's file, the
 * plot script and the verification table. */
#include "reproduce_kit.h"
#include "../measure/accel_choice.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include "../run/cell_row.h"
#include "../run/csv.h"
#include "../run/output.h"
#include "markdown.h"
#include "reproduce.h"
#include "../workloads/resources.h"
#include "../../prims/checked_alloc.h"
#include "../workloads/trace.h"
#include "../workloads/workload.h"

/* ------------------------------------------------------------ options */

void rp_usage_options(FILE *out)
{
    fprintf(out,
            "  options (every experiment):\n"
            "  --out DIR      output folder (default results/EXPERIMENT-<date-time>): EXPERIMENT.csv (the run\n"
            "                 CSV's columns plus table, variant, grid_res), EXPERIMENT_tables.md, EXPERIMENT_*.png\n"
            "  --threads N    threads (default 1); woo92 times every trace on 1 thread whatever N is, havran\n"
            "                 times them on N; the untimed work (ray sets, Embree's answers) always uses N\n"
            "  --repeat N     timed repeats after one verified warm-up, each paired with Embree's,\n"
            "                 median reported (default 3)\n"
            "  --quick        small images and 1 repeat: the same tables in seconds (for tests only)\n"
            "  --scenes LIST  only these of the experiment's scenes, comma-separated, by the paper's name or\n"
            "                 ours (havran: balls,spd:tree); woo92's tables need all of its scenes\n"
            "  --accels LIST  spd only: the accelerators to trace the protocol through (default bvh-gs)\n"
            "  --no-plots     do not call the experiment's plot script at the end\n"
            "  --quiet        no progress on stderr\n"
            "  --memcap MIB   refuse work estimated above MIB MiB before allocating it (default: half the memory\n"
            "                 this process may use; docs/limits.md)\n"
            "  Every measurement is verified against Embree: exit 1 on any real mismatch, 2 on bad input.\n");
}

int rp_parse(rp_kit *k, int argc, char **argv, void (*usage)(FILE *))
{
    static const struct option opts[] = {
        {"out", required_argument, NULL, 'o'},  {"threads", required_argument, NULL, 't'},
        {"repeat", required_argument, NULL, 'n'}, {"quick", no_argument, NULL, 'k'},
        {"no-plots", no_argument, NULL, 'P'},   {"quiet", no_argument, NULL, 'q'},
        {"memcap", required_argument, NULL, 'M'},
        {"scenes", required_argument, NULL, 's'}, {"accels", required_argument, NULL, 'a'},
        {"help", no_argument, NULL, 'h'},       {NULL, 0, NULL, 0},
    };
    rp_opts *o = &k->o;
    uint64_t memcap_mib = 0; /* --memcap MIB; 0: the default (scenes/memory_cap.h) */
    char why[512];
    memset(o, 0, sizeof *o);
    o->threads = 1;
    o->repeat = 3;
    o->plots = true;
    optind = 1;
    opterr = 0;
    int ch;
    while ((ch = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        char *end;
        long v;
        switch (ch) {
        case 'o': o->out = optarg; break;
        case 't':
        case 'n':
            errno = 0;
            v = strtol(optarg, &end, 10);
            if (errno || end == optarg || *end || v < 1 || v > (ch == 't' ? 1024 : 1000)) {
                fprintf(stderr, "accelbench reproduce: --%s %s: expected an integer in 1..%d\n", ch == 't' ? "threads" : "repeat",
                        optarg, ch == 't' ? 1024 : 1000);
                return 2;
            }
            if (ch == 't') o->threads = (int)v;
            else o->repeat = (int)v, o->repeat_given = true;
            break;
        case 'k': o->quick = true; break;
        case 's': o->scenes = optarg; break;
        case 'a': o->accels = optarg; break;
        case 'M':
            if (resources_parse_memcap(optarg, &memcap_mib, why, sizeof why)) {
                fprintf(stderr, "accelbench reproduce: %s\n", why);
                return 2;
            }
            break;
        case 'P': o->plots = false; break;
        case 'q': o->quiet = true; break;
        case 'h': usage(stdout); return 1;
        default:
            fprintf(stderr, "accelbench reproduce: unknown or incomplete option '%s' (see accelbench reproduce --help)\n",
                    argv[optind - 1]);
            return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "accelbench reproduce: unexpected argument '%s' (see accelbench reproduce --help)\n", argv[optind]);
        return 2;
    }
    if (o->quick && !o->repeat_given) o->repeat = 1;
    /* The memory cap, and the threads' stacks against it (resources.h). */
    memory_cap_set_mib(memcap_mib);
    if (resources_check_threads(o->threads, "--threads", why, sizeof why)) {
        fprintf(stderr, "accelbench reproduce: %s\n", why);
        return 2;
    }
    return 0;
}

bool rp_begin(rp_kit *k, const char *experiment, const scene_def *scenes, int nscenes, int timed_threads, int argc,
              char **argv, const char *no_accels, const char *no_scenes, int *rc)
{
    k->experiment = experiment;
    k->scenes = scenes, k->nscenes = nscenes;
    int parsed = rp_parse(k, argc, argv, reproduce_usage);
    if (parsed) {
        *rc = parsed == 1 ? 0 : parsed;
        return false;
    }
    const char *refused = k->o.accels && no_accels ? "--accels" : k->o.scenes && no_scenes ? "--scenes" : NULL;
    if (refused) {
        fprintf(stderr, "accelbench reproduce %s: %s: %s\n", experiment, refused,
                k->o.accels && no_accels ? no_accels : no_scenes);
        *rc = 2;
        return false;
    }
    k->timed_threads = timed_threads ? timed_threads : k->o.threads;
    return true;
}

int rp_select_scenes(const rp_kit *k, bool *use)
{
    for (int i = 0; i < k->nscenes; i++) use[i] = !k->o.scenes;
    if (!k->o.scenes) return 0;
    const char *p = k->o.scenes;
    int chosen = 0;
    while (*p) {
        size_t n = strcspn(p, ",");
        int found = -1;
        for (int i = 0; i < k->nscenes && found < 0; i++) {
            const scene_def *d = &k->scenes[i];
            if ((strlen(d->image) == n && !strncmp(p, d->image, n)) || (strlen(d->load) == n && !strncmp(p, d->load, n)))
                found = i;
        }
        if (found < 0) {
            char known[512] = "";
            for (int i = 0; i < k->nscenes; i++)
                snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", i ? ", " : "", k->scenes[i].image);
            fprintf(stderr, "accelbench reproduce %s: --scenes: unknown scene '%.*s' (known: %s)\n", k->experiment, (int)n, p,
                    known);
            return 2;
        }
        chosen += !use[found];
        use[found] = true;
        p += n;
        if (*p == ',') p++;
    }
    if (!chosen) {
        fprintf(stderr, "accelbench reproduce %s: --scenes: no scene named\n", k->experiment);
        return 2;
    }
    return 0;
}

int rp_start(rp_kit *k)
{
    for (int i = 0; i < k->nscenes; i++) k->label[i] = k->scenes[i].load;
    machine_describe(&k->mi);
    char prefix[64];
    snprintf(prefix, sizeof prefix, "%s-", k->experiment);
    if (output_folder(k->o.out, prefix, k->out_dir, sizeof k->out_dir)) return 2;
    snprintf(k->csv_path, sizeof k->csv_path, "%s/%s.csv", k->out_dir, k->experiment);
    k->csv = fopen(k->csv_path, "w");
    if (!k->csv) {
        fprintf(stderr, "accelbench: %s: cannot write: %s\n", k->csv_path, strerror(errno));
        return 2;
    }
    char header[CSV_HEADER_MAX];
    csv_header(header, sizeof header);
    if (fprintf(k->csv, "table,variant,grid_res,%s\n", header) < 0 || fflush(k->csv) != 0) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", k->csv_path, strerror(errno));
        fclose(k->csv);
        k->csv = NULL;
        return 2;
    }
    k->wall0 = clock_ms();
    return 0;
}

/* ------------------------------------------------------------ scenes */

static void free_sets(rp_kit *k)
{
    for (int i = 0; i < k->nsets; i++) cell_rays_release(&k->cells[i]);
    k->nsets = 0;
}

void rp_close_scene(rp_kit *k)
{
    free_sets(k);
    if (k->ref) k->ref->ops->destroy(k->ref);
    verifier_free(k->ver);
    if (k->s) scene_free(k->s);
    k->ref = NULL;
    k->ver = NULL;
    k->s = NULL;
}

/* The scene to load for def d: its own, or its stand-in when d's catalogue
 * file is not on this machine (the reason goes in `reason`, else ""). */
static const char *scene_to_load(const scene_def *d, char *reason, size_t len)
{
    reason[0] = 0;
    char where[1024];
    if (!d->standin || scene_catalogue_available(d->load, where, sizeof where)) return d->load;
    snprintf(reason, len, "%s", where);
    return d->standin;
}

int rp_open_scene(rp_kit *k, int idx)
{
    char err[512];
    rp_close_scene(k);
    const scene_def *d = &k->scenes[idx];
    const char *name = scene_to_load(d, k->standin_reason[idx], sizeof k->standin_reason[idx]);
    if (k->standin_reason[idx][0])
        fprintf(stderr, "reproduce %s: STAND-IN: the paper's %s is measured on %s, because %s is not on this machine: %s\n",
                k->experiment, d->image, name, d->load, k->standin_reason[idx]);
    k->label[idx] = name;
    if (k->standin_reason[idx][0]) snprintf(k->shown[idx], sizeof k->shown[idx], "%s (STAND-IN for %s)", name, d->load);
    else snprintf(k->shown[idx], sizeof k->shown[idx], "%s", name);
    double t0 = clock_ms();
    k->s = scene_load(name, err, sizeof err);
    if (!k->s) {
        fprintf(stderr, "accelbench: %s\n", err);
        return -1;
    }
    k->ref = build_reference(k->s, k->o.threads, err, sizeof err);
    if (!k->ref) {
        fprintf(stderr, "accelbench: %s: reference build failed: %s\n", name, err);
        return -1;
    }
    k->ver = verifier_new(k->s, VERIFY_JUDGE_SECONDS);
    k->cur = idx;
    if (!k->o.quiet)
        fprintf(stderr, "scene %s: %u primitives, loaded in %.0f ms\n", name, k->s->prims.count, clock_ms() - t0);
    return 0;
}

void rp_prepare_sets(rp_kit *k, int w, int h, int spp, bool corners, int depth, const char *const *workloads, int n)
{
    free_sets(k);
    workload_opts wo = {.width = w, .height = h, .spp = spp, .corners = corners, .depth = depth, .seed = 1,
                        .threads = k->o.threads};
    for (int i = 0; i < n && i < RP_SETS_MAX; i++) {
        rayset_t *rs = workload_find(workloads[i])->make(k->s, k->ref, &wo);
        cell_rays_init(&k->cells[k->nsets++], k->s, k->ref, k->ver, rs, k->o.threads);
    }
    k->width = w, k->height = h, k->spp = spp;
}

/* ------------------------------------------------------------ measuring */

static void write_rows(rp_kit *k, const meas *m, const char *table, const char *variant)
{
    for (int i = 0; i < m->nsets; i++) {
        fprintf(k->csv, "%s,%s,%s,", table, variant, m->res_str);
        csv_write_row(k->csv, &m->rows[i]);
    }
}

/* A grid's resolution from its res_x/res_y/res_z statistics into res and
 * "AxBxC"; nothing for a structure that reports none. */
static void grid_res(const csv_row *row, int res[3], char *str, size_t len)
{
    static const char *const axis[3] = {"res_x", "res_y", "res_z"};
    int found = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < row->nstats; j++)
            if (!strcmp(row->stats[j].name, axis[i])) res[i] = (int)row->stats[j].value, found++;
    if (found == 3) snprintf(str, len, "%dx%dx%d", res[0], res[1], res[2]);
    else res[0] = res[1] = res[2] = 0, str[0] = 0;
}

/* Add one cell of m (ray set i) and report its real mismatches. */
static void add_cell(rp_kit *k, meas *m, int i, const cell_result *cr, const char *table, const char *variant)
{
    const csv_row *row = &cr->row;
    const verify_result *vr = &cr->vr;
    m->ms += row->trace_ms, m->ms_min += row->trace_ms_min, m->ms_max += row->trace_ms_max, m->build_ms += row->build_ms;
    m->embree_ms += row->embree_ms;
    m->rays += row->rays;
    m->mem = row->mem_bytes;
    counters_add(&m->c, &row->counters);
    m->agree += vr->agree;
    for (int c = 0; c < MM_CLASSES; c++) m->mm[c] += vr->mismatches[c];
    if (!vr->mismatches[MM_REAL]) return;
    k->any_real = true;
    fprintf(stderr, "accelbench: REAL MISMATCH: %s %s [%s] on %s/%s: %llu rays\n", table, variant, m->params,
            k->label[k->cur], m->workload[i], (unsigned long long)vr->mismatches[MM_REAL]);
    for (uint32_t j = 0; j < vr->nlisted; j++)
        if (vr->listed[j].cls == MM_REAL) {
            const mismatch_t *x = &vr->listed[j];
            fprintf(stderr, "  ray %u: got prim %d t=%.7g, embree prim %d t=%.7g\n", x->ray,
                    x->got.prim == HIT_NONE ? -1 : (int)x->got.prim, x->got.t,
                    x->ref.prim == HIT_NONE ? -1 : (int)x->ref.prim, x->ref.t);
        }
}

meas *rp_measure(rp_kit *k, const char *table, const char *variant, const char *name, const char *settings)
{
    accel_config ac;
    char err[1024], spec[1200];
    /* The variant goes through --accels' parser (accel_choice.h): NAME[k=v,...], exactly one instance. */
    snprintf(spec, sizeof spec, settings && *settings ? "%s[%s]" : "%s", name, settings);
    if (accel_spec_expand(spec, &ac, 1, err, sizeof err) != 1) {
        fprintf(stderr, "accelbench: reproduce: %s\n", err);
        return NULL;
    }
    ac.params.threads = k->timed_threads;
    accel_settle_params(ac.ops, &ac.params); /* machine-dependent values as they will run */
    params_format(&ac.params, ac.params_str, sizeof ac.params_str);
    resources_bound_accel_params(&ac.params); /* the build within --memcap */
    snprintf(ac.label, sizeof ac.label, "%s", name);

    for (int i = 0; i < k->nmeas; i++) {
        meas *m = &k->store[i];
        if (m->scene == k->cur && m->spp == k->spp && m->width == k->width && m->height == k->height && m->ops == ac.ops &&
            strcmp(m->params, ac.params_str) == 0) {
            write_rows(k, m, table, variant);
            return m;
        }
    }
    if (k->nmeas == RP_MEAS_MAX) {
        fprintf(stderr, "accelbench: reproduce: more than %d measurements\n", RP_MEAS_MAX);
        return NULL;
    }
    meas *m = &k->store[k->nmeas++];
    memset(m, 0, sizeof *m);
    m->scene = k->cur, m->spp = k->spp, m->width = k->width, m->height = k->height, m->ops = ac.ops;
    snprintf(m->params, sizeof m->params, "%s", ac.params_str);
    m->nsets = k->nsets;
    row_settings st = {.cell = {.threads = k->timed_threads, .repeat = k->o.repeat}, .width = k->width,
                       .height = k->height, .spp = k->spp, .mi = &k->mi};
    for (int i = 0; i < k->nsets; i++) {
        cell_result cr;
        if (measure_cell_row(&k->cells[i], &ac, &st, &cr)) return NULL;
        if (i == 0) grid_res(&cr.row, m->res, m->res_str, sizeof m->res_str);
        snprintf(m->workload[i], sizeof m->workload[i], "%s", cr.row.workload);
        /* The stored row outlives the scene and the ray sets: point it at
         * strings that live as long as the run. */
        cr.row.scene = k->label[k->cur];
        cr.row.params = m->params;
        cr.row.workload = m->workload[i];
        m->rows[i] = cr.row;
        add_cell(k, m, i, &cr, table, variant);
    }
    write_rows(k, m, table, variant);
    if (!k->o.quiet)
        fprintf(stderr, "  [%3d] %-8s %-16s %-16s %s %dx%d spp %d: %.1f ms (%.0f-%.0f), %.2f tests/ray, real mismatches %llu (%.0f s)\n",
                k->nmeas, table, variant, k->label[k->cur], m->res_str[0] ? m->res_str : name, k->width, k->height,
                k->spp, m->ms, m->ms_min, m->ms_max, rp_tests(m), (unsigned long long)m->mm[MM_REAL],
                (clock_ms() - k->wall0) / 1e3);
    return m;
}

/* ------------------------------------------------------------ the end */

/* Write text to path; 0, or 1 after a one-line error. */
static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "accelbench: %s: cannot write: %s\n", path, strerror(errno));
        return 1;
    }
    bool ok = fputs(text, f) != EOF && fflush(f) == 0;
    int e = errno;
    if (fclose(f) != 0 && ok) ok = false, e = errno;
    if (!ok) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", path, strerror(e));
        return 1;
    }
    return 0;
}

int rp_finish(rp_kit *k, int rc, void (*report)(void *ctx, FILE *f), void *ctx, const char *plot_script)
{
    /* Every row went through stdio: its error flag and the close say whether all of them reached the file. */
    bool csv_ok = !ferror(k->csv) && fflush(k->csv) == 0;
    int csv_errno = errno;
    if (fclose(k->csv) != 0 && csv_ok) csv_ok = false, csv_errno = errno;
    k->csv = NULL;
    if (!csv_ok && rc == 0) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", k->csv_path, strerror(csv_errno));
        rc = 1;
    }
    if (rc) {
        rp_close_scene(k);
        return rc;
    }
    rp_close_scene(k);
    double wall_s = (clock_ms() - k->wall0) / 1e3;
    char *md = NULL;
    size_t mdlen = 0;
    FILE *f = open_memstream(&md, &mdlen);
    if (!f) checked_alloc_failed(0, "the tables' Markdown (open_memstream)");
    report(ctx, f);
    fprintf(f, "Measured in %.0f s (%d measurements). CSV: %s\n", wall_s, k->nmeas, k->csv_path);
    fclose(f);
    fputs(md, stdout);
    fflush(stdout);
    char path[1300];
    snprintf(path, sizeof path, "%s/%s_tables.md", k->out_dir, k->experiment);
    rc = write_text(path, md);
    free(md);
    if (rc) return rc;
    if (!k->o.quiet) fprintf(stderr, "wrote %s and %s (%.1f s)\n", k->csv_path, path, wall_s);
    if (k->o.plots && plot_script) run_plot_script(plot_script, k->csv_path, k->o.quiet);
    if (k->any_real) {
        fprintf(stderr, "accelbench: reproduce %s: REAL mismatches against Embree (see above and the Verification table)\n",
                k->experiment);
        return 1;
    }
    return 0;
}

void rp_timed_paths(const rp_kit *k, char *buf, size_t len)
{
    buf[0] = 0;
    for (int i = 0; i < k->nmeas; i++) {
        const char *p = k->store[i].rows[0].timed_path;
        if (p && !strstr(buf, p)) snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", buf[0] ? ", " : "", p);
    }
}

/* Sum the rays, agreements and mismatch classes of n measurements into one report row. */
static void verification_row(FILE *f, const char *name, meas *const *list, int n, uint64_t *rays_out, uint64_t *real_out)
{
    uint64_t rays = 0, agree = 0, mm[MM_CLASSES] = {0};
    for (int i = 0; i < n; i++) {
        rays += list[i]->rays, agree += list[i]->agree;
        for (int c = 0; c < MM_CLASSES; c++) mm[c] += list[i]->mm[c];
    }
    md_row(f, "%s|%d|%llu|%llu|%llu|%llu|%llu|%llu|%llu|%llu", name, n, (unsigned long long)rays,
               (unsigned long long)agree, (unsigned long long)mm[MM_EDGE], (unsigned long long)mm[MM_ORIGIN],
               (unsigned long long)mm[MM_TOL], (unsigned long long)mm[MM_REFWRONG], (unsigned long long)mm[MM_REAL],
               (unsigned long long)mm[MM_UNJUDGED]);
    *rays_out = rays, *real_out = mm[MM_REAL];
}

void rp_verification(const rp_kit *k, FILE *f, const rp_group *groups, int ngroups)
{
    md_section(f, "Verification against Embree",
                   "Every measurement's warm-up answers, ray by ray, against Embree's (harness/measure/verify.h: edge = within float "
                   "noise of an edge or silhouette, origin = the ray starts within rounding of the disputed surface, tol = "
                   "same primitive with t off by float noise, refwrong = the exact judge sides with us, real = a bug, "
                   "unjudged = the judge's time budget ran out).");
    md_table(f, "Table|measurements:|rays:|agree:|edge:|origin:|tol:|refwrong:|real:|unjudged:");
    uint64_t rays, real;
    for (int g = 0; g < ngroups; g++) verification_row(f, groups[g].name, groups[g].list, groups[g].n, &rays, &real);
    meas *all[RP_MEAS_MAX];
    for (int i = 0; i < k->nmeas; i++) all[i] = (meas *)&k->store[i];
    verification_row(f, "all (each measurement once)", all, k->nmeas, &rays, &real);
    md_end(f);
    /* The last row is every measurement once: the verdict. */
    md_para(f, "%s: %llu real mismatches in %d measurements (%llu rays).", real ? "FAILED" : "verified",
                (unsigned long long)real, k->nmeas, (unsigned long long)rays);
}
