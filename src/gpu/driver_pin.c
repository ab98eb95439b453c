/*
 * vkDestroyInstance makes the loader dlclose() every ICD it opened. Mesa's
 * drivers keep heap blocks reachable only from their own globals (caches,
 * the LLVM JIT of lavapipe); once a driver is unmapped, LeakSanitizer, which
 * runs at exit and scans only the globals of modules still loaded, reports
 * those blocks as leaks from an unknown module. Opening each ICD ourselves
 * with RTLD_NODELETE turns the loader's dlclose() into a no-op, so the
 * sanitized test run keeps leak detection on and real leaks still show.
 *
 * Manifests are found as the Vulkan loader finds them on Linux
 * (LoaderInterfaceArchitecture.md, "Driver Discovery on Linux"): the files or
 * folders listed in $VK_DRIVER_FILES or $VK_ICD_FILENAMES when set, else the
 * vulkan/icd.d folder of each of $XDG_CONFIG_DIRS, /etc, $XDG_DATA_HOME and
 * $XDG_DATA_DIRS.
 */
#include "gpu/driver_pin.h"

#include <dirent.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#define MANIFEST_MAX (64 * 1024)

static void pin_library(const char *manifest, const char *lib)
{
    char path[4096];
    /* A library path with a slash but not absolute is relative to the
     * manifest; a bare name goes through the dynamic linker's search. */
    if (lib[0] != '/' && strchr(lib, '/')) {
        const char *slash = strrchr(manifest, '/');
        int dir_len = slash ? (int)(slash - manifest) : 1;
        snprintf(path, sizeof(path), "%.*s/%s", dir_len, slash ? manifest : ".", lib);
    } else {
        snprintf(path, sizeof(path), "%s", lib);
    }
    /* The handle is never closed: holding it is the point. */
    (void)dlopen(path, RTLD_LAZY | RTLD_LOCAL | RTLD_NODELETE);
}

static void pin_manifest(const char *manifest)
{
    FILE *f = fopen(manifest, "rb");
    if (!f)
        return;
    char *text = malloc(MANIFEST_MAX + 1);
    size_t n = text ? fread(text, 1, MANIFEST_MAX, f) : 0;
    fclose(f);
    if (!text)
        return;
    text[n] = '\0';
    cJSON *root = cJSON_Parse(text);
    free(text);
    const cJSON *lib = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(root, "ICD"), "library_path");
    if (cJSON_IsString(lib) && lib->valuestring[0])
        pin_library(manifest, lib->valuestring);
    cJSON_Delete(root);
}

static int is_json(const char *name)
{
    size_t n = strlen(name);
    return n > 5 && strcmp(name + n - 5, ".json") == 0;
}

/* A manifest file, or a folder of them. */
static void pin_path(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return;
    if (!S_ISDIR(st.st_mode)) {
        pin_manifest(path);
        return;
    }
    DIR *dir = opendir(path);
    if (!dir)
        return;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        if (!is_json(e->d_name))
            continue;
        char file[4096];
        snprintf(file, sizeof(file), "%s/%s", path, e->d_name);
        pin_manifest(file);
    }
    closedir(dir);
}

/* Each entry of a ':'-separated list, with `suffix` appended. */
static void pin_list(const char *list, const char *suffix)
{
    while (list && *list) {
        const char *end = strchr(list, ':');
        size_t len = end ? (size_t)(end - list) : strlen(list);
        if (len > 0) {
            char path[4096];
            snprintf(path, sizeof(path), "%.*s%s", (int)len, list, suffix);
            pin_path(path);
        }
        list = end ? end + 1 : NULL;
    }
}

static void pin_all(void)
{
    const char *files = getenv("VK_DRIVER_FILES");
    if (!files || !*files)
        files = getenv("VK_ICD_FILENAMES");
    if (files && *files) {
        pin_list(files, "");
        return;
    }
    const char *config = getenv("XDG_CONFIG_DIRS");
    pin_list(config && *config ? config : "/etc/xdg", "/vulkan/icd.d");
    pin_path("/etc/vulkan/icd.d");
    const char *data_home = getenv("XDG_DATA_HOME");
    const char *home = getenv("HOME");
    if (data_home && *data_home) {
        pin_list(data_home, "/vulkan/icd.d");
    } else if (home && *home) {
        char path[4096];
        snprintf(path, sizeof(path), "%s/.local/share/vulkan/icd.d", home);
        pin_path(path);
    }
    const char *data = getenv("XDG_DATA_DIRS");
    pin_list(data && *data ? data : "/usr/local/share:/usr/share", "/vulkan/icd.d");
}

void gpu_pin_driver(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, pin_all);
}
