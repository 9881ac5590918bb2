# The same fit with R's flexmix: a mixture of Gaussian regressions with common slopes (the
# columns of H) and mode-specific intercepts (the mu_i) and variances, FLXMRglmfix(varFix = FALSE),
# started from the posteriors at tofcomp's start (CASE.r0.f64).
# flexmix's M-step fits the common slopes by least squares weighted by the posteriors alone
# (not by posterior / sigma_i^2) and its sigma_i with a degrees-of-freedom correction, so it is not
# the exact maximization step of §5: its fixed point is near, not at, the maximum likelihood.
# Its stopping rule: relative change of the log-likelihood below `tolerance`.
#
# Usage: Rscript em_flexmix.R DIR CASE ITERATIONS TOLERANCE MAX_ITERATIONS
#   prints one JSON line: per-iteration time (ITERATIONS iterations), the converged fit.
suppressMessages(library(flexmix))
args <- commandArgs(trailingOnly = TRUE)
dir <- args[1]; name <- args[2]; iterations <- as.integer(args[3])
tolerance <- as.numeric(args[4]); max_iterations <- as.integer(args[5])
meta <- readLines(file.path(dir, paste0(name, ".json")), warn = FALSE)
num <- function(key) as.integer(sub(paste0('.*"', key, '": ([0-9]+).*'), "\\1", meta))
k <- num("K"); p <- num("p"); m <- num("M")
h <- matrix(readBin(file.path(dir, paste0(name, ".h.f64")), "double", k * p, endian = "little"),
            nrow = k, ncol = p, byrow = TRUE)
y <- readBin(file.path(dir, paste0(name, ".y.f64")), "double", k, endian = "little")
r0 <- matrix(readBin(file.path(dir, paste0(name, ".r0.f64")), "double", k * m, endian = "little"),
             nrow = k, ncol = m, byrow = TRUE)
data <- data.frame(y = y, h)
fixed <- as.formula(paste("~ 0 +", paste(colnames(data)[-1], collapse = " + ")))
run <- function(iter_max, tol) {
  flexmix(y ~ 1, data = data, k = m, cluster = r0,
          model = FLXMRglmfix(fixed = fixed, varFix = FALSE),
          control = list(iter.max = iter_max, tolerance = tol, minprior = 0, verbose = 0))
}
timed <- system.time(short <- run(iterations, 0))[["user.self"]] + 0
timed_fit <- system.time(full <- run(max_iterations, tolerance))[["user.self"]] + 0
cat(sprintf(paste0('{"peer": "flexmix", "case": "%s", "s_per_iteration": %.6g, ',
                   '"iterations": %d, "log_likelihood": %.10f, "converged": %s, "fit_s": %.6g}\n'),
            name, timed / short@iter, full@iter, as.numeric(logLik(full)),
            if (full@converged) "true" else "false", timed_fit))
